#include "fluidtex/io/color_spaces.h"

#include <algorithm>
#include <cstdlib>

#include <OpenImageIO/color.h>

#include "fluidtex/io/image_io.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"

namespace fluidtex {

struct ColorSpaces::Config {
  mutable OIIO::ColorConfig oiio;  // geterror() clears its message
  std::string source;  // what the config is, for messages: the file, $OCIO or "OpenImageIO's built-in config"
  explicit Config(const std::string& file) : oiio(file) {}

  bool has(const std::string& name) const {
    const std::vector<std::string> names = oiio.getColorSpaceNames();
    return std::find(names.begin(), names.end(), name) != names.end();
  }
  /// "its spaces: a, b, c".
  std::string spaces() const {
    std::string list;
    for (const std::string& n : oiio.getColorSpaceNames()) list += (list.empty() ? "" : ", ") + n;
    return "its spaces: " + list;
  }
  /// "'NAME' is not a colour space of SOURCE (its spaces: a, b, c)".
  std::string unknown(const std::string& name) const {
    return "'" + name + "' is not a colour space of " + source + " (" + spaces() + ")";
  }
};

std::string ColorSpaceOptions::config_file() const {
  if (!managed()) return "";
  if (!config.empty()) return config;
  const char* env = std::getenv("OCIO");
  return env ? std::string(env) : std::string();
}

ColorSpaces::ColorSpaces(const ColorSpaceOptions& options) {
  if (!options.managed()) return;
  const std::string file = options.config_file();
  auto config = std::make_shared<Config>(file);
  config->source = !options.config.empty() ? options.config
                   : !file.empty()         ? "$OCIO (" + file + ")"
                                           : std::string("OpenImageIO's built-in config");
  // Without a file OpenImageIO says so, and uses its built-in spaces.
  const std::string why = one_line(config->oiio.geterror());
  if (!file.empty() && !why.empty())
    throw InputError(options.config.empty() ? "$OCIO" : options.config, "cannot read the OpenColorIO config: " + why);
  const auto check = [&](const std::string& name, const char* option) {
    if (!name.empty() && !config->has(name)) throw InputError(std::string("--") + option, config->unknown(name));
    return name;
  };
  exemplar_ = check(options.exemplar, "exemplar-colorspace");
  working_ = check(options.working, "working-colorspace");
  if (working_.empty()) {
    // Linear Rec. 709, as unmanaged runs blend in: the names configs give it.
    for (const char* name : {"lin_rec709", "Linear Rec.709 (sRGB)", "Utility - Linear - sRGB", "linear", "Linear"}) {
      if (config->has(name)) {
        working_ = name;
        break;
      }
    }
    if (working_.empty())
      throw InputError("--working-colorspace",
                       "not given, and " + config->source + " has no linear Rec. 709 space to default to: name one");
  }
  output_ = options.output.empty() ? working_ : check(options.output, "output-colorspace");
  config_ = std::move(config);
}

void ColorSpaces::convert(Image& image, const std::string& from, const std::string& to, int alpha) const {
  if (from == to) return;
  const OIIO::ColorProcessorHandle processor = config_->oiio.createColorProcessor(from, to);
  if (!processor) {
    throw InputError(config_->source,
                     "no transform from '" + from + "' to '" + to + "': " + one_line(config_->oiio.geterror()));
  }
  if (processor->isNoOp()) return;
  // Colour in the first three channels (alpha, where there is one, after
  // them, as in fluidtex's outputs), never converted.
  if (image.channels >= 3 && (alpha < 0 || alpha >= 3)) {
    const auto stride = static_cast<OIIO::stride_t>(sizeof(float));
    processor->apply(image.pixels.data(), image.width, image.height, 3, stride, stride * image.channels,
                     stride * image.channels * image.width);
    return;
  }
  // Grey: converted as (v, v, v), its first channel kept.
  for (std::size_t i = 0; i < static_cast<std::size_t>(image.width) * image.height; ++i) {
    float* p = image.pixel(i);
    float rgb[3] = {p[0], p[0], p[0]};
    processor->apply(rgb);
    p[0] = rgb[0];
  }
}

Image ColorSpaces::read_exemplar(const std::string& path, std::string& warning) const {
  warning.clear();
  if (!managed()) {
    ImageFile decoded = read_image_file(path, ImageValues::Decoded);
    if (!decoded.rules_apply) {
      warning = path + ": names the colour space '" + decoded.color_space +
                "', which fluidtex reads as linear Rec. 709 unless colour is managed: give --exemplar-colorspace "
                "(and --ocio-config or $OCIO)";
    }
    return std::move(decoded.image);
  }
  ImageFile stored = read_image_file(path, ImageValues::AsStored);
  std::string from = exemplar_;
  if (from.empty()) {
    if (stored.color_space.empty())
      throw InputError(path, "names no colour space: give --exemplar-colorspace (" + config_->source + ", " +
                                 config_->spaces() + ")");
    if (!config_->has(stored.color_space))
      throw InputError(path, "names the colour space '" + stored.color_space + "', which " + config_->source +
                                 " lacks (" + config_->spaces() + "): give --exemplar-colorspace");
    from = stored.color_space;
  }
  convert(stored.image, from, working_, stored.alpha);
  return std::move(stored.image);
}

Image ColorSpaces::to_output(Image image) const {
  if (managed()) convert(image, working_, output_, image.channels == 4 ? 3 : -1);
  return image;
}

}  // namespace fluidtex
