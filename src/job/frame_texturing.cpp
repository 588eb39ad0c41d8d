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
  synth.sharpness = so.sharpness;
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

AtlasOptions job_atlas_options(const JobOptions& options) {
  AtlasOptions atlas = options.synthesis.atlas;
  atlas.max_tiles = FramePattern(options.output.atlas()).has_udim() ? kMaxUdimTiles : 1;
  return atlas;
}

double exemplar_span(const TrackingOptions& resolved, const SynthesisJobOptions& so) {
  return resolved.exemplar_tile_size(so.exemplar_size) / resolved.uv_scale;
}

namespace {

/// The frame's layers (kFrameLayers) that the job writes, of tile `udim`
/// (the UDIM number; patterns without <UDIM> ignore it), each with its pixel
/// encoding.
void write_frame_layers(const JobOptions& options, int frame, int udim, const FrameSynthesis& textured,
                        const ImageWriteOptions& color_write) {
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const std::string pattern = options.layer_pattern(i);
    if (pattern.empty()) continue;
    const FrameLayer& layer = kFrameLayers[i];
    write_image(FramePattern(pattern).path(frame, udim), layer.make(textured), layer_write_options(layer, color_write));
  }
}

/// The material of frame `frame`'s OBJ: its atlas and its height and normal
/// layers, UDIM tiles by the <UDIM> token.
MaterialMaps frame_material(const JobOptions& options, int frame, double bump_height) {
  MaterialMaps maps(std::filesystem::absolute(FramePattern(options.output.atlas()).path(frame)).string());
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const std::string pattern = options.layer_pattern(i);
    if (pattern.empty()) continue;
    const std::string path = std::filesystem::absolute(FramePattern(pattern).path(frame)).string();
    if (kFrameLayers[i].slot == MaterialSlot::Height) {
      maps.displacement = path;
      maps.bump_height = bump_height;
    } else if (kFrameLayers[i].slot == MaterialSlot::Normal) {
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

/// A synthesis's counts added into `total` (its images are left).
void add_counts(SynthesisResult& total, const SynthesisResult& tile) {
  total.chart_texels += tile.chart_texels;
  total.uncovered_texels += tile.uncovered_texels;
  total.margin_texels += tile.margin_texels;
  total.clamped_texels += tile.clamped_texels;
  total.dominant_texels += tile.dominant_texels;
  total.binned_triangles += tile.binned_triangles;
  total.projected_triangles += tile.projected_triangles;
}

/// What making a frame's tiles took: their summed counts and seconds.
struct TilesMade {
  SynthesisResult total;  ///< counts only
  double synth_seconds = 0.0, write_seconds = 0.0;
};

/// Each tile of `atlas`: its texel map, texels (`texels(atlas, map)`, either
/// method) and writes, the atlas and its layers. UDIM tiles are made and
/// written one at a time, the last first: a frame whose tile 1001 exists
/// has all of its tiles. `tile_size`: the exemplar's size on the surface
/// (--bump-height's unit).
template <class Texels>
TilesMade make_tiles(const SurfaceIndex& surface, const Atlas& atlas, const JobOptions& options,
                     const ColorSpaces& colors, int frame, double tile_size, Texels&& texels) {
  const FramePattern atlas_pattern(options.output.atlas());
  const ImageWriteOptions write = atlas_write_options(options, frame, tile_size, colors);
  TilesMade made;
  for (int tile = atlas.tiles - 1; tile >= 0; --tile) {
    auto t0 = Clock::now();
    const TexelMap map = build_texel_map(surface, atlas, tile);
    const SynthesisResult result = texels(atlas, map);
    made.synth_seconds += seconds_since(t0);
    // A texel that is not finite is a bug, never an output (options bound
    // the scales that could overflow).
    for (float v : result.color.pixels) {
      if (!std::isfinite(v))
        throw InternalError("frame " + std::to_string(frame) + ": the atlas has non-finite texels");
    }
    add_counts(made.total, result);
    t0 = Clock::now();
    const int udim = udim_number(tile);
    ImageWriteOptions tile_write = write;
    if (atlas_pattern.has_udim()) tile_write.metadata.emplace_back("fluidtex:udim", std::to_string(udim));
    write_image(atlas_pattern.path(frame, udim),
                write.color_space.empty() ? result.color : colors.to_output(result.color), tile_write);
    write_frame_layers(options, frame, udim,
                       FrameSynthesis{atlas, map, result, options.synthesis.bump_height * tile_size}, tile_write);
    made.write_seconds += seconds_since(t0);
  }
  return made;
}

/// The synthesis numbers of a frame's atlas in `stats`.
void add_atlas_stats(const Atlas& atlas, const TilesMade& made, FrameStats& stats) {
  const SynthesisResult& total = made.total;
  stats.uncovered_fraction = total.uncovered_fraction();
  stats.extra.emplace_back("packing_efficiency", atlas.packing_efficiency);
  stats.extra.emplace_back("charts", static_cast<double>(atlas.charts.size()));
  stats.extra.emplace_back("atlas_tiles", static_cast<double>(atlas.tiles));
  stats.extra.emplace_back("chart_texels", static_cast<double>(total.chart_texels));
  stats.extra.emplace_back("margin_texels", static_cast<double>(total.margin_texels));
  stats.extra.emplace_back("binned_triangles", static_cast<double>(total.binned_triangles));
  stats.extra.emplace_back("projected_triangles", static_cast<double>(total.projected_triangles));
  stats.extra.emplace_back("clamped_fraction",
                           total.chart_texels ? static_cast<double>(total.clamped_texels) / total.chart_texels : 0.0);
  stats.extra.emplace_back("dominant_fraction",
                           total.chart_texels ? static_cast<double>(total.dominant_texels) / total.chart_texels : 0.0);
  stats.extra.emplace_back("texels_per_second", made.synth_seconds > 0 ? total.chart_texels / made.synth_seconds : 0.0);
}

/// A frame's atlas, its tiles (make_tiles) and its UV mesh, with the
/// synthesis numbers and stage seconds in `stats`.
template <class Texels>
void atlas_frame(const SurfaceIndex& surface, const JobOptions& options, const ColorSpaces& colors, int frame,
                 FrameStats& stats, double tile_size, Texels&& texels) {
  auto t0 = Clock::now();
  const Atlas atlas = build_atlas(surface, job_atlas_options(options));
  stats.seconds.emplace_back("atlas", seconds_since(t0));
  const TilesMade made = make_tiles(surface, atlas, options, colors, frame, tile_size, std::forward<Texels>(texels));
  stats.seconds.emplace_back("synthesis", made.synth_seconds);
  // An OBJ names its atlas through a material (<stem>.mtl, map_Kd; disp,
  // bump and norm for the height and normal atlases), so a DCC imports it
  // textured.
  t0 = Clock::now();
  write_uv_mesh(FramePattern(options.output.mesh()).path(frame), atlas_uv_mesh(surface, atlas),
                frame_material(options, frame, options.synthesis.bump_height * tile_size));
  stats.seconds.emplace_back("write", made.write_seconds + seconds_since(t0));
  add_atlas_stats(atlas, made, stats);
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
