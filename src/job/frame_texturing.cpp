#include "fluidtex/job/frame_texturing.h"

#include <cmath>
#include <filesystem>
#include <utility>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/frame_layers.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/strings.h"
#include "fluidtex/util/timing.h"
#include "fluidtex/util/version.h"

namespace fluidtex {

Exemplar load_exemplar(const std::string& path, bool displacement, const ColorSpaces& colors, std::string* warning) {
  std::string said;
  Image image = displacement ? read_image(path) : colors.read_exemplar(path, said);
  if (warning) *warning = said;
  if (displacement && image.channels >= 3) {
    Image grey;
    grey.width = image.width, grey.height = image.height, grey.channels = 1;
    grey.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = luminance_at<float>(image, i);
    image = std::move(grey);
  } else if (displacement && image.channels == 2) {
    image.channels = 1;  // grey + alpha: keep grey
    for (std::size_t i = 0; i < static_cast<std::size_t>(image.width) * image.height; ++i)
      image.pixels[i] = image.pixels[2 * i];
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  }
  if (image.channels == 2) throw InputError(path, "exemplar has 2 channels (expected grey, RGB or RGBA)");
  for (float v : image.pixels) {
    if (!std::isfinite(v)) throw InputError(path, "exemplar has NaN or infinite pixels");
  }
  return Exemplar(std::move(image));
}

TextureSource load_texture_source(const JobOptions& options, std::string* warning) {
  ColorSpaces colors(options.synthesis.color);
  Exemplar exemplar = load_exemplar(options.exemplar, options.synthesis.displacement, colors, warning);
  return TextureSource{std::move(colors), std::move(exemplar)};
}

SynthesisOptions synthesis_options(const TrackingOptions& resolved, const SynthesisJobOptions& so) {
  SynthesisOptions synth;
  synth.blend = so.blend;
  synth.scheme = so.scheme;
  synth.weight_cutoff = so.weight_cutoff;
  synth.uv_scale = resolved.uv_scale;
  synth.radius = resolved.d();
  // One exemplar tile spans (2 + β)·d at s = 1 unless --exemplar-size says:
  // a patch's disk shows most of a tile, each patch a different part of it
  // (its random anchor).
  synth.tile_size = resolved.exemplar_tile_size(so.exemplar_size);
  synth.projection_tolerance = resolved.mpt();  // as the tracker's coverage test
  synth.aov = !so.aov.empty();
  return synth;
}

double exemplar_span(const TrackingOptions& resolved, const SynthesisJobOptions& so) {
  return resolved.exemplar_tile_size(so.exemplar_size) / resolved.uv_scale;
}

namespace {

/// The frame's layers (kFrameLayers) that the job writes, each with its
/// pixel encoding; returns the material's maps for the OBJ.
MaterialMaps write_frame_layers(const JobOptions& options, int frame, const FrameSynthesis& textured,
                                const ImageWriteOptions& color_write) {
  MaterialMaps maps(std::filesystem::absolute(FramePattern(options.output.atlas()).path(frame)).string());
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const std::string pattern = options.layer_pattern(i);
    if (pattern.empty()) continue;
    const FrameLayer& layer = kFrameLayers[i];
    const std::string path = std::filesystem::absolute(FramePattern(pattern).path(frame)).string();
    write_image(path, layer.make(textured), layer_write_options(layer, color_write));
    if (layer.slot == MaterialSlot::Height) {
      maps.displacement = path;
      maps.bump_height = textured.bump_height;
    } else if (layer.slot == MaterialSlot::Normal) {
      maps.normal = path;
    }
  }
  return maps;
}

/// How frame `frame`'s colour atlas is written: depth, compression, layout,
/// where it comes from (metadata) and, managed, the output colour space
/// (a height atlas, --displacement, is data: never converted).
ImageWriteOptions atlas_write_options(const JobOptions& options, int frame, double tile_size,
                                      const ColorSpaces& colors) {
  const SynthesisJobOptions& so = options.synthesis;
  ImageWriteOptions write;
  write.depth = so.float_output ? PixelDepth::Float : PixelDepth::Default;
  write.compression = so.compression;
  write.dwa_level = so.dwa_level;
  write.layout = so.layout;
  write.metadata = {{"fluidtex:version", version_line()},
                    {"fluidtex:frame", std::to_string(frame)},
                    {"fluidtex:settings", options.output.provenance},
                    {"fluidtex:exemplarSize", format_number(tile_size / options.tracking.uv_scale)}};
  if (colors.managed() && !so.displacement) write.color_space = colors.output();
  return write;
}

/// A frame's atlas, texel map, texels (`texels(atlas, map)`, either method)
/// and writes, with the synthesis numbers and stage seconds in `stats`.
/// `tile_size`: the exemplar's size on the surface (--bump-height's unit).
template <class Texels>
void atlas_frame(const SurfaceIndex& surface, const JobOptions& options, const ColorSpaces& colors, int frame,
                 FrameStats& stats, double tile_size, Texels&& texels) {
  const SynthesisJobOptions& so = options.synthesis;
  auto t0 = Clock::now();
  const Atlas atlas = build_atlas(surface, so.atlas);
  stats.seconds.emplace_back("atlas", seconds_since(t0));
  t0 = Clock::now();
  const TexelMap map = build_texel_map(surface, atlas);
  const SynthesisResult result = texels(atlas, map);
  const double synth_seconds = seconds_since(t0);
  stats.seconds.emplace_back("synthesis", synth_seconds);

  // A texel that is not finite is a bug, never an output (options bound the
  // scales that could overflow).
  for (float v : result.color.pixels) {
    if (!std::isfinite(v)) throw InternalError("frame " + std::to_string(frame) + ": the atlas has non-finite texels");
  }

  t0 = Clock::now();
  const ImageWriteOptions write = atlas_write_options(options, frame, tile_size, colors);
  write_image(FramePattern(options.output.atlas()).path(frame),
              write.color_space.empty() ? result.color : colors.to_output(result.color), write);
  // An OBJ names its atlas through a material (<stem>.mtl, map_Kd; disp,
  // bump and norm for the height and normal atlases), so a DCC imports it
  // textured.
  const MaterialMaps maps =
      write_frame_layers(options, frame, FrameSynthesis{atlas, map, result, so.bump_height * tile_size}, write);
  write_uv_mesh(FramePattern(options.output.mesh()).path(frame), atlas_uv_mesh(surface, atlas), maps);
  stats.seconds.emplace_back("write", seconds_since(t0));

  stats.uncovered_fraction = result.uncovered_fraction();
  stats.extra.emplace_back("packing_efficiency", atlas.packing_efficiency);
  stats.extra.emplace_back("charts", static_cast<double>(atlas.charts.size()));
  stats.extra.emplace_back("chart_texels", static_cast<double>(result.chart_texels));
  stats.extra.emplace_back("margin_texels", static_cast<double>(result.margin_texels));
  stats.extra.emplace_back("binned_triangles", static_cast<double>(result.binned_triangles));
  stats.extra.emplace_back("projected_triangles", static_cast<double>(result.projected_triangles));
  stats.extra.emplace_back(
      "clamped_fraction", result.chart_texels ? static_cast<double>(result.clamped_texels) / result.chart_texels : 0.0);
  stats.extra.emplace_back("texels_per_second", synth_seconds > 0 ? result.chart_texels / synth_seconds : 0.0);
}

}  // namespace

void synthesize_frame(const SurfaceIndex& surface, const std::vector<Patch>& patches, const TrackingOptions& resolved,
                      const TextureSource& source, const JobOptions& options, int frame, FrameStats& stats) {
  atlas_frame(surface, options, source.colors, frame, stats,
              resolved.exemplar_tile_size(options.synthesis.exemplar_size),
              [&](const Atlas& atlas, const TexelMap& map) {
                return synthesize(surface, atlas, map, patches, source.exemplar,
                                  synthesis_options(resolved, options.synthesis));
              });
}

void synthesize_flowmap_frame(const SurfaceIndex& surface, const FlowMapFrame& flow, const TextureSource& source,
                              const JobOptions& options, int frame, FrameStats& stats, double tile_size) {
  atlas_frame(surface, options, source.colors, frame, stats, tile_size, [&](const Atlas& atlas, const TexelMap& map) {
    return synthesize_flowmap(surface, atlas, map, flow, source.exemplar, options.synthesis.blend,
                              !options.synthesis.aov.empty());
  });
}

}  // namespace fluidtex
