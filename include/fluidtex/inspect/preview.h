/// @file preview.h
/// @brief `fluidtex preview`: a finished run's textured frames rendered to
/// PNG (RUN/preview/frame.####.png) with the software renderer (render.h),
/// optionally with diagnostic overlays (overlays.h) and a contact sheet.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "fluidtex/inspect/render.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct PreviewOptions {
  std::string run_dir;        ///< the output folder of a fluidtex run
  std::string frames;         ///< --frames; empty = every UV mesh found
  std::string mesh_pattern;   ///< --mesh; empty = the run's (RUN/job.toml), else RUN/mesh.####.obj
  std::string atlas_pattern;  ///< --atlas; empty = the run's (RUN/job.toml), else RUN/atlas.####.exr
  RenderOptions render;
  /// --camera EX,EY,EZ,TX,TY,TZ[,FOV]: a perspective camera replacing
  /// render's orthographic view; empty = render as given.
  std::string camera;
  /// The run's input, needed by the overlays only; an empty pattern takes
  /// the input RUN/job.toml records (with its reading options).
  InputOptions input;
  /// Overlays drawn over the frames: "borders" (patch boundary edges, one
  /// colour per patch; needs RUN/state/), "states" (disk centres by state;
  /// needs RUN/state/), "velocity" (vertex velocity arrows).
  std::vector<std::string> overlays;
  double velocity_scale = 4.0;  ///< arrows are v·dt·K long
  int arrow_spacing = 24;       ///< pixels between arrows
  int sheet = 0;                ///< > 0: RUN/preview/sheet.png of every K-th rendered frame
  bool sheet_only = false;      ///< the contact sheet only, no per-frame PNGs

  /// Whether the overlay `name` is asked for.
  bool overlay(const std::string& name) const;
  /// InputError for a bad value (sizes, spacing, --sheet-only without
  /// --sheet, overlays without the input pattern).
  void validate() const;

  /// The options of `preview` as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f);
};

struct PreviewSummary {
  std::size_t frames = 0;     ///< frames rendered
  std::string frame_pattern;  ///< where they went (empty with sheet_only)
  std::size_t sheet_frames = 0;
  std::string sheet_path;  ///< empty without a sheet
};

PreviewSummary run_preview(const PreviewOptions& given);

/// `render` with the perspective camera of `text`, EX,EY,EZ,TX,TY,TZ[,FOV]
/// (eye, target, vertical field of view in degrees). InputError for text
/// that is not 6 or 7 finite numbers.
RenderOptions with_camera(RenderOptions render, const std::string& text);

template <class Self, class F>
void PreviewOptions::for_each_option(Self& o, F&& f) {
  using namespace shared_options;
  f(OptionInfo{.name = "run", .help = "The output folder of a fluidtex run", .positional = true, .required = true},
    o.run_dir);
  f(with_help(kFrames, "Frames to render, e.g. 1-48x8 (default: all)"), o.frames);
  f(kView, o.render.view);
  f(OptionInfo{.name = "camera",
               .help = "Perspective camera EX,EY,EZ,TX,TY,TZ[,FOV]: eye, target, vertical field of view in degrees "
                       "(default 40); up is +z (+y when looking along z). Replaces --view"},
    o.camera);
  f(OptionInfo{.name = "width", .help = "Image width in pixels", .bounds = between(1, 16384)}, o.render.width);
  f(OptionInfo{.name = "height",
               .help = "Image height of the perspective camera (default: width * 3/4; orthographic views follow the "
                       "framing)",
               .bounds = between(1, 16384)},
    o.render.height);
  f(OptionInfo{.name = "mesh", .help = "UV mesh pattern, .obj or .ply (default: the run's)"}, o.mesh_pattern);
  f(OptionInfo{.name = "atlas", .help = "Atlas pattern (default: the run's)"}, o.atlas_pattern);
  const char* const overlays = "Overlays";
  f(OptionInfo{.name = "overlay",
               .help = "Draw over the frames (comma list): borders, states (disk centres by state), velocity "
                       "(arrows); reads the input RUN/job.toml records, or -i",
               .choices = "borders,states,velocity",
               .group = overlays},
    o.overlays);
  OptionInfo input = with_help(kInput, "The run's input frame pattern (needed by --overlay)");
  input.group = overlays;
  f(input, o.input.pattern);
  InputOptions::for_each_reading_option(o.input, [&f, overlays](OptionInfo info, auto& field) {
    info.group = overlays;
    f(info, field);
  });
  f(OptionInfo{.name = "velocity-scale",
               .help = "Velocity arrows are v * dt * K long (K frames of motion)",
               .bounds = between(1e-6, 1e6),
               .group = overlays},
    o.velocity_scale);
  f(OptionInfo{.name = "arrow-spacing",
               .help = "Pixels between velocity arrows",
               .bounds = between(1, 16384),
               .group = overlays},
    o.arrow_spacing);
  const char* const sheet = "Contact sheet";
  f(OptionInfo{.name = "sheet",
               .help = "Also write RUN/preview/sheet.png: every K-th rendered frame in a grid",
               .bounds = at_least(0),
               .group = sheet},
    o.sheet);
  f(OptionInfo{.name = "sheet-only", .help = "Write the contact sheet only, no per-frame PNGs", .group = sheet},
    o.sheet_only);
}

}  // namespace fluidtex
