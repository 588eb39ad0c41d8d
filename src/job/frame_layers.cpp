#include "fluidtex/job/frame_layers.h"

#include "fluidtex/util/options.h"

namespace fluidtex {

namespace {

/// "name (help), ..." of the AOV layers (`with_help`), or their names alone.
std::string aov_list(bool with_help) {
  std::string list;
  for (const FrameLayer& layer : kFrameLayers) {
    if (layer.option) continue;
    if (!list.empty()) list += ", ";
    list += layer.name;
    if (with_help) list += std::string(" (") + layer.help + ")";
  }
  return list;
}

}  // namespace

const char* aov_layer_names() {
  static const std::string names = aov_list(false);
  return names.c_str();
}

const char* aov_layer_help() {
  static const std::string help = "Extra atlas layers in OUT/aov/: " + aov_list(true);
  return help.c_str();
}

ImageWriteOptions layer_write_options(const FrameLayer& layer, const ImageWriteOptions& atlas_write) {
  ImageWriteOptions write;
  switch (layer.pixels) {
    case LayerPixels::Data:
      write = atlas_write;
      write.data = true;
      break;
    case LayerPixels::Float: write.depth = PixelDepth::Float; break;
    case LayerPixels::IdColour: break;
  }
  write.channel_names = option_detail::split_choices(layer.channels);
  return write;
}

}  // namespace fluidtex
