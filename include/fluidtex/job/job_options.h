/// @file job_options.h
/// @brief Everything `fluidtex run` is told, and its one options table:
/// `JobOptions::for_each_option` lists every option of the job once (name,
/// help, accepted values, field; util/options.h). The command line, `--help`,
/// `--print-config`, `--config` and the run's `OUT/job.toml` (written by
/// run_job, read back by `fluidtex eval`) all come from it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fluidtex/io/color_spaces.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/job/frame_layers.h"
#include "fluidtex/texture/atlas.h"
#include "fluidtex/texture/flowmap.h"
#include "fluidtex/texture/synthesis.h"
#include "fluidtex/tracking/advection.h"
#include "fluidtex/tracking/options.h"
#include "fluidtex/util/options.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

/// Which patch states a run keeps in OUT/state/ (--keep-state).
enum class KeepState {
  All,   ///< every frame's: `fluidtex synth` can texture any frame again
  Last,  ///< the newest only: enough to --resume, a fraction of the disk
};
inline constexpr EnumName<KeepState> kKeepStateNames[] = {{KeepState::All, "all"}, {KeepState::Last, "last"}};
constexpr const auto& enum_names(KeepState) { return kKeepStateNames; }

struct OutputOptions {
  std::string dir;            ///< -o: output folder
  std::string atlas_pattern;  ///< --atlas; empty = DIR/atlas.####.exr
  std::string mesh_pattern;   ///< --mesh; empty = DIR/mesh.####.obj
  /// The patterns of the layers with an option of their own (kFrameLayers:
  /// --displacement-atlas, --normal-atlas), by layer; empty = not written.
  std::array<std::string, kFrameLayerCount> layer_patterns;
  bool resume = false;                    ///< --resume: continue the job in OUT after its last complete frame
  bool force = false;                     ///< --force: replace another job's outputs in OUT
  KeepState keep_state = KeepState::All;  ///< --keep-state
  bool debug_views = false;               ///< --debug-views: patch/disk PLYs per frame
  bool write_state = true;                ///< OUT/state/patches.####.bin after every frame (not an option)
  /// The job's settings hash (settings_hash in job_record.h), stamped in every
  /// atlas as `fluidtex:settings` (not an option: run and synth set it).
  std::string provenance;

  /// The effective patterns (defaults filled in); InputError when a given
  /// pattern has no frame token or an unsupported extension.
  std::string atlas() const;
  std::string mesh() const;

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(shared_options::with_help(shared_options::kOutput, "Output folder (required)"), o.dir);
    f(OptionInfo{.name = "atlas",
                 .help = "Atlas file pattern (.exr, .png, .tif) (default: OUT/atlas.####.exr); with <UDIM> in it "
                         "(OUT/atlas.####.<UDIM>.exr), a frame that --texel-density puts in more than one "
                         "--atlas-size square is written as UDIM tiles 1001, 1002, ...",
                 .role = OptionRole::OutputPath},
      o.atlas_pattern);
    f(OptionInfo{.name = "mesh",
                 .help = "UV mesh file pattern (.obj, .ply) (default: OUT/mesh.####.obj)",
                 .role = OptionRole::OutputPath},
      o.mesh_pattern);
    for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
      const FrameLayer& layer = kFrameLayers[i];
      if (layer.option)
        f(OptionInfo{.name = layer.option, .help = layer.help, .role = OptionRole::OutputPath}, o.layer_patterns[i]);
    }
    f(OptionInfo{.name = "resume",
                 .help = "Continue the job in OUT after its last complete frame (refused when an option that "
                         "changes the output, the exemplar or the build differs from OUT/job.toml)",
                 .role = OptionRole::Free},
      o.resume);
    f(OptionInfo{.name = "force",
                 .help = "Replace the outputs of an earlier job in OUT (without it, a run into a folder that holds "
                         "one is refused)",
                 .role = OptionRole::Free},
      o.force);
    f(OptionInfo{.name = "keep-state",
                 .help = "Patch states kept in OUT/state/: all (fluidtex synth can texture any frame) or last (the "
                         "newest, enough for --resume)",
                 .role = OptionRole::Free},
      o.keep_state);
    f(OptionInfo{.name = "debug-views",
                 .help = "Write per-frame PLYs of the patches and of the disks coloured by state",
                 .role = OptionRole::Free},
      o.debug_views);
  }
};

/// How each frame's atlas is made and written (Sec. 6.4).
struct SynthesisJobOptions {
  AtlasOptions atlas;
  /// --exemplar-size: scene units one exemplar tile spans at --uv-scale 1;
  /// unset = (2 + β)·d (TrackingOptions::exemplar_tile_size).
  std::optional<double> exemplar_size;
  ColorSpaceOptions color;                           ///< --ocio-config and the --*-colorspace names
  Blend blend = Blend::ContrastPreserving;           ///< --blend
  double weight_cutoff = 0.1;                        ///< --weight-cutoff (SynthesisOptions::weight_cutoff)
  double sharpness = 3.0;                            ///< --blend-sharpness (SynthesisOptions::sharpness; docs/look.md)
  SynthesisScheme scheme = SynthesisScheme::Raster;  ///< --synthesis
  std::vector<std::string> aov;                      ///< --aov: the AOV layers of kFrameLayers
  bool displacement = false;                         ///< --displacement: one-channel height atlas from a grey exemplar
  bool float_output = false;                         ///< --float: 32-bit EXR/TIFF instead of half / 16-bit
  ExrCompression compression = ExrCompression::Piz;  ///< --compression (EXR atlases)
  int dwa_level = 45;                                ///< --dwa-level (dwaa, dwab)
  TextureLayout layout = TextureLayout::Scanline;    ///< --texture-layout
  double bump_height = 0.02;                         ///< --bump-height, × the exemplar's size on the surface
  bool track_only = false;                           ///< --track-only: no atlas, no mesh (state and stats only)

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    AtlasOptions::for_each_option(o.atlas, f);
    f(OptionInfo{.name = "exemplar-size",
                 .help = "Size of one exemplar tile on the surface in scene units, at --uv-scale 1 (auto: (2 + beta) x "
                         "radius, which follows the first frame's size unless --radius is given): the same value "
                         "gives every shot the same texture size",
                 .bounds = between(1e-9, 1e9)},
      o.exemplar_size);
    ColorSpaceOptions::for_each_option(o.color, f);
    f(OptionInfo{.name = "blend",
                 .help = "contrast: Eq. 7, contrast preserving (results clamped to [0,1]); linear: sum(w R)/sum(w); "
                         "histogram: histogram preserving (Heitz and Neyret 2018), the exemplar's own colours"},
      o.blend);
    f(OptionInfo{.name = "weight-cutoff",
                 .help = "Each texel blends its patches' weights lowered by this fraction of its largest one: "
                         "fewer, sharper overlaps (0: every overlapping patch, as the paper)",
                 .bounds = between(0.0, 0.95)},
      o.weight_cutoff);
    f(OptionInfo{.name = "blend-sharpness",
                 .help = "Each texel's patch weights are raised to this power (relative to its largest): most "
                         "texels show one patch, with narrow transitions (1: as they are, the paper)",
                 .bounds = between(1.0, 64.0)},
      o.sharpness);
    f(OptionInfo{.name = "synthesis",
                 .help = "raster: patch triangles rasterised in atlas space; exact: per-texel projection "
                         "(reference, slow)"},
      o.scheme);
    f(OptionInfo{.name = "aov", .help = aov_layer_help(), .choices = aov_layer_names()}, o.aov);
    f(OptionInfo{.name = "displacement", .help = "Write a one-channel height atlas (the exemplar is turned to grey)"},
      o.displacement);
    f(OptionInfo{.name = "float", .help = "32-bit float EXR/TIFF instead of half / 16-bit"}, o.float_output);
    f(OptionInfo{.name = "compression",
                 .help = "EXR atlas compression: piz (default), zip, none, rle, zips (lossless); pxr24, b44, b44a, "
                         "dwaa, dwab (lossy)"},
      o.compression);
    f(OptionInfo{.name = "dwa-level",
                 .help = "Compression level of dwaa and dwab (OpenEXR's default 45; higher: smaller, lossier)",
                 .bounds = between(1, 1000)},
      o.dwa_level);
    f(OptionInfo{.name = "texture-layout",
                 .help = "Atlas layout: scanline, tiled (64x64 tiles) or mipmap (tiles and every MIP level; EXR)"},
      o.layout);
    f(OptionInfo{.name = "bump-height",
                 .help = "Height of white above black in the height and normal atlases, as a fraction of the "
                         "exemplar's size on the surface",
                 .bounds = above(0)},
      o.bump_height);
    f(OptionInfo{.name = "track-only",
                 .help = "Track patches only: state files and stats, no atlas or mesh",
                 .role = OptionRole::Mode},
      o.track_only);
  }
  void validate() const;
};

struct JobOptions {
  InputOptions input;
  OutputOptions output;
  std::string exemplar;  ///< -e: exemplar image
  int threads = 0;       ///< worker threads; 0 = all cores
  std::uint64_t seed = 1;
  TexturingMethod method = TexturingMethod::Patches;  ///< --method
  FlowMapOptions flowmap;                             ///< --flowmap-period, --flowmap-axis (--method flowmap)
  TrackingOptions tracking;                           ///< patches; flowmap takes d, β (tile size) and s from it
  /// Poisson update without the coverage test: a candidate rejected by a disk
  /// is never seeded, even where no live patch covers the surface (the
  /// paper's plain dart throwing; docs/method.md).
  bool no_coverage_check = false;
  Advection advection = Advection::Euler;          ///< --advection
  PatchMotion patch_motion = PatchMotion::Smooth;  ///< --patch-motion
  SynthesisJobOptions synthesis;

  /// Every option of the job, in --help order, each with its --help section
  /// in OptionInfo::group.
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f);

  /// InputError for any bad option, and for options the method does not
  /// have (flowmap: --resume, --track-only, --debug-views).
  void validate() const;

  /// The file pattern of kFrameLayers[layer] (its option's, or an AOV's
  /// OUT/aov/NAME.####.exr), empty when the job does not write it;
  /// InputError for a pattern without a frame token or not EXR.
  std::string layer_pattern(std::size_t layer) const;
};

/// The job's options bound to `o`, for the command line and config files.
std::vector<OptionRef> option_table(JobOptions& o);

/// The configuration as TOML: what --print-config prints, and OUT/job.toml;
/// its first line, a comment, names the build (version_line()).
std::string job_toml(const JobOptions& o);

/// Sets the options of `o` (and of `extra`, the caller's own) that the config
/// file `path` gives, except those `skip(name)` names (the command line's).
/// Reads the job.toml of runs made by fluidtex 0.1 too (their console
/// settings and "0 = automatic" lengths). InputError naming the file for a
/// missing file, a malformed one, an unknown option or a bad value.
void apply_job_file(JobOptions& o, const std::string& path, const std::function<bool(const std::string&)>& skip,
                    std::vector<OptionRef> extra = {});

/// The options a config file (`--print-config` output, a run's OUT/job.toml)
/// gives, over the defaults (apply_job_file).
JobOptions read_job_file(const std::string& path);

/// The options a finished run was made with, from RUN_DIR/job.toml. A
/// folder moved or copied since: an output pattern the job recorded inside
/// its output folder (`--atlas`, `--mesh`, the layers') is taken at the
/// same place in RUN_DIR, where its files now are; one outside stays (the
/// recorded output folder itself is left: callers set it).
JobOptions read_job_manifest(const std::string& run_dir);

template <class Self, class F>
void JobOptions::for_each_option(Self& o, F&& f) {
  // Sub-structs' options take the section of the place they are listed in.
  auto in_section = [&f](const char* group) {
    return [&f, group](OptionInfo info, auto& field) {
      if (*info.group == '\0') info.group = group;
      f(info, field);
    };
  };
  InputOptions::for_each_option(o.input, in_section(""));
  OutputOptions::for_each_option(o.output, in_section(""));
  f(shared_options::with_help(shared_options::kExemplar,
                              "Exemplar texture (any format OpenImageIO reads; 8/16-bit files are taken as sRGB and "
                              "linearised, float files as linear, unless colour is managed: --exemplar-colorspace)"),
    o.exemplar);
  f(shared_options::kThreads, o.threads);
  f(shared_options::kSeed, o.seed);
  f(OptionInfo{.name = "method",
               .help = "patches: Gagnon et al. 2019; flowmap: the two-phase advected-UV baseline (same outputs, no "
                       "state)",
               .group = "Method"},
    o.method);
  FlowMapOptions::for_each_option(o.flowmap, in_section("Method"));
  const char* const paper = "Method (Tables 3, 4)";
  TrackingOptions::for_each_option(o.tracking, in_section(paper));
  f(OptionInfo{.name = "no-coverage-check",
               .help = "Poisson update without the coverage test: a candidate rejected by a disk is never seeded, "
                       "even where no patch covers the surface (the paper's plain dart throwing)",
               .group = paper},
    o.no_coverage_check);
  f(OptionInfo{.name = "advection",
               .help = "Patch advection: euler (x + v_f dt, the solver's own step) or heun (second order, for "
                       "velocities sampled at the frame's instant)",
               .group = paper},
    o.advection);
  f(OptionInfo{.name = "patch-motion",
               .help = "smooth: a patch moves by one cubic map fitted to its advected vertices; vertex: each vertex "
                       "alone (the paper)",
               .group = paper},
    o.patch_motion);
  SynthesisJobOptions::for_each_option(o.synthesis, in_section("Synthesis"));
}

}  // namespace fluidtex
