/// @file color_spaces.h
/// @brief Colour management through OpenColorIO (OpenImageIO's
/// ColorConfig): the space an exemplar's values are in, the space synthesis
/// blends in, and the space a colour atlas is written in.
///
/// Unmanaged unless a space is named (--exemplar-colorspace,
/// --working-colorspace, --output-colorspace): then read_image's own rules
/// apply (integer files sRGB, float files linear, Rec. 709 primaries) and no
/// OpenColorIO config is read. Managed, the config is --ocio-config, else
/// $OCIO, else OpenImageIO's built-in one (linear, sRGB, Rec709); an
/// exemplar is converted once from its space to the working space, and a
/// colour atlas once from the working space to the output space, which its
/// `oiio:ColorSpace` names.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "fluidtex/geometry/image.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

struct ColorSpaceOptions {
  std::string config;    ///< --ocio-config; empty: $OCIO, else OpenImageIO's built-in spaces
  std::string exemplar;  ///< --exemplar-colorspace; empty: the space the file names
  std::string working;   ///< --working-colorspace; empty: linear Rec. 709
  std::string output;    ///< --output-colorspace; empty: the working space

  /// Whether a space is named (otherwise fluidtex's own rules, no config).
  bool managed() const { return !exemplar.empty() || !working.empty() || !output.empty(); }
  /// The config file a managed job reads (--ocio-config, else $OCIO); empty
  /// when unmanaged or with OpenImageIO's built-in config.
  std::string config_file() const;

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = "ocio-config",
                 .help = "OpenColorIO config for the --*-colorspace names (default: $OCIO, else OpenImageIO's "
                         "built-in linear, sRGB and Rec709)",
                 .group = "Colour",
                 .role = OptionRole::InputPath},
      o.config);
    f(OptionInfo{.name = "exemplar-colorspace",
                 .help = "Colour space of the exemplar's values (default: the one its file names; with no space "
                         "named anywhere, integer files are sRGB and float files linear Rec. 709)",
                 .group = "Colour"},
      o.exemplar);
    f(OptionInfo{.name = "working-colorspace",
                 .help = "Colour space synthesis blends in (default: linear Rec. 709)",
                 .group = "Colour"},
      o.working);
    f(OptionInfo{.name = "output-colorspace",
                 .help = "Colour space of the colour atlas, named in its oiio:ColorSpace (default: the working "
                         "space; PNG and TIFF are written as its values say, so name an encoded space such as sRGB)",
                 .group = "Colour"},
      o.output);
  }
};

/// The spaces of a job, checked against the config when it is managed.
class ColorSpaces {
 public:
  /// Unmanaged: nothing is converted.
  ColorSpaces() = default;
  /// InputError naming the option when the config cannot be read or a name
  /// is not one of its spaces (the line lists them).
  explicit ColorSpaces(const ColorSpaceOptions& options);

  bool managed() const { return config_ != nullptr; }
  /// The managed working and output spaces' names.
  const std::string& working() const { return working_; }
  const std::string& output() const { return output_; }

  /// Reads the colour exemplar at `path` into the working space: managed,
  /// converted once from --exemplar-colorspace or the space its file names
  /// (InputError when neither names a space of the config); unmanaged,
  /// read_image's rules, and `warning` says so when the file names a space
  /// those rules do not know (read as linear Rec. 709).
  Image read_exemplar(const std::string& path, std::string& warning) const;
  /// `image` (colour in the working space) in the output space; unmanaged
  /// or when the two are the same space, unchanged.
  Image to_output(Image image) const;

 private:
  void convert(Image& image, const std::string& from, const std::string& to, int alpha) const;

  struct Config;  // the OpenColorIO config (OpenImageIO's ColorConfig)
  std::shared_ptr<const Config> config_;
  std::string exemplar_, working_, output_;
};

}  // namespace fluidtex
