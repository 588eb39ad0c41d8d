/// @file frame_layers.h
/// @brief The image layers a frame can write beside its colour atlas, in one
/// table: each layer's name, the option that asks for it, how its pixels are
/// written, the material slot that names it in the OBJ's material, and how it
/// is made from the frame's synthesis. The options (--displacement-atlas,
/// --normal-atlas, --aov), the job's list of files, the writes and the
/// material all read this table: a new layer is a row here and the function
/// that makes its image.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string>

#include "fluidtex/io/image_io.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/maps.h"
#include "fluidtex/texture/synthesis.h"

namespace fluidtex {

/// What a frame's texturing made, from which its layers are derived.
struct FrameSynthesis {
  const Atlas& atlas;
  const TexelMap& map;
  const SynthesisResult& result;
  double bump_height;  ///< scene units: --bump-height × the exemplar's size on the surface
};

/// How a layer's pixels are written.
enum class LayerPixels : std::uint8_t {
  Data,      ///< data (no colour space) at the atlas's depth, compression and layout, with its metadata
  Float,     ///< data as 32-bit float, default compression
  IdColour,  ///< a colour per patch id, at the format's default depth
};

/// The slot of the OBJ's material that names a layer (MaterialMaps).
enum class MaterialSlot : std::uint8_t {
  None,
  Height,  ///< disp, and bump with the height of white above black
  Normal,  ///< norm
};

/// One per-frame image layer.
struct FrameLayer {
  const char* name;
  /// The option giving its file pattern (EXR), or nullptr: an AOV, asked for
  /// by `--aov NAME` and written to OUT/aov/NAME.####.exr.
  const char* option;
  const char* help;  ///< the option's help (an AOV's: what it holds)
  LayerPixels pixels;
  const char* channels;  ///< channel names, comma separated ("" : OpenImageIO's default)
  MaterialSlot slot;
  Image (*make)(const FrameSynthesis&);
};

inline constexpr FrameLayer kFrameLayers[] = {
    {.name = "displacement",
     .option = "displacement-atlas",
     .help = "Also write a height atlas (the colour's luminance, one channel, .exr) to this pattern, named by the "
             "OBJ's material as disp and bump",
     .pixels = LayerPixels::Data,
     .channels = "Y",
     .slot = MaterialSlot::Height,
     .make = [](const FrameSynthesis& f) { return height_map(f.result.color); }},
    {.name = "normal",
     .option = "normal-atlas",
     .help = "Also write a tangent-space normal atlas (from the height, --bump-height; .exr) to this pattern, named "
             "by the OBJ's material as norm",
     .pixels = LayerPixels::Data,
     .channels = "R,G,B",
     .slot = MaterialSlot::Normal,
     .make =
         [](const FrameSynthesis& f) { return normal_map(height_map(f.result.color), f.map, f.atlas, f.bump_height); }},
    {.name = "weight",
     .option = nullptr,
     .help = "sum w",
     .pixels = LayerPixels::Float,
     .channels = "",
     .slot = MaterialSlot::None,
     .make = [](const FrameSynthesis& f) { return f.result.weight; }},
    {.name = "count",
     .option = nullptr,
     .help = "patches per texel",
     .pixels = LayerPixels::Float,
     .channels = "",
     .slot = MaterialSlot::None,
     .make = [](const FrameSynthesis& f) { return f.result.count; }},
    {.name = "patch",
     .option = nullptr,
     .help = "the dominant patch, a colour per patch",
     .pixels = LayerPixels::IdColour,
     .channels = "",
     .slot = MaterialSlot::None,
     .make = [](const FrameSynthesis& f) { return f.result.patch; }},
};
inline constexpr std::size_t kFrameLayerCount = std::size(kFrameLayers);

/// The AOV layers' names, comma separated (--aov's choices).
const char* aov_layer_names();

/// The AOV layers with what each holds ("weight (sum w), count (...)"), for --aov's help.
const char* aov_layer_help();

/// The write options of `layer`, from the colour atlas's (`atlas_write`).
ImageWriteOptions layer_write_options(const FrameLayer& layer, const ImageWriteOptions& atlas_write);

}  // namespace fluidtex
