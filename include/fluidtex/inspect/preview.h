/// @file preview.h
/// @brief `fluidtex preview`: a finished run's textured frames rendered to
/// PNG (RUN/preview/frame.####.png) with the software renderer (render.h),
/// optionally with diagnostic overlays (overlays.h) and a contact sheet.
#pragma once

#include <cstddef>
#include <string>

#include "fluidtex/inspect/render.h"
#include "fluidtex/io/sequence.h"

namespace fluidtex {

struct PreviewOptions {
  std::string run_dir;        ///< the output folder of a fluidtex run
  std::string frames;         ///< --frames; empty = every UV mesh found
  std::string mesh_pattern;   ///< --mesh; empty = the run's (RUN/job.toml), else RUN/mesh.####.obj
  std::string atlas_pattern;  ///< --atlas; empty = the run's (RUN/job.toml), else RUN/atlas.####.exr
  RenderOptions render;
  /// The run's input, needed by the overlays only; an empty pattern takes
  /// the input RUN/job.toml records (with its reading options).
  InputOptions input;
  bool borders = false;         ///< overlay: patch boundary edges, one colour per patch (needs RUN/state/)
  bool states = false;          ///< overlay: disk centres by state (needs RUN/state/)
  bool velocity = false;        ///< overlay: vertex velocity arrows
  double velocity_scale = 4.0;  ///< arrows are v·dt·K long
  int arrow_spacing = 24;       ///< pixels between arrows
  int sheet = 0;                ///< > 0: RUN/preview/sheet.png of every K-th rendered frame
  bool sheet_only = false;      ///< the contact sheet only, no per-frame PNGs

  bool overlays() const { return borders || states || velocity; }
  /// InputError for a bad value (sizes, spacing, --sheet-only without
  /// --sheet, overlays without the input pattern).
  void validate() const;
};

struct PreviewSummary {
  std::size_t frames = 0;     ///< frames rendered
  std::string frame_pattern;  ///< where they went (empty with sheet_only)
  std::size_t sheet_frames = 0;
  std::string sheet_path;  ///< empty without a sheet
};

PreviewSummary run_preview(const PreviewOptions& given);

}  // namespace fluidtex
