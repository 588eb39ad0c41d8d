#include "fluidtex/inspect/preview.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

#include "fluidtex/inspect/overlays.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

void PreviewOptions::validate() const {
  if (render.width < 1) throw InputError("", "--width must be at least 1");
  if (render.height < 0) throw InputError("", "--height must be at least 1");
  if (sheet < 0) throw InputError("", "--sheet must be at least 1");
  if (sheet_only && sheet == 0) throw InputError("", "--sheet-only needs --sheet K");
  if (arrow_spacing < 1) throw InputError("", "--arrow-spacing must be at least 1");
  if (overlays() && input.pattern.empty()) {
    const char* first = borders ? "borders" : states ? "states" : "velocity";
    throw InputError(
        "", std::string("--overlay ") + first +
                ": needs the run's input sequence (-i/--input PATTERN, as given to run; RUN/job.toml records it)");
  }
}

namespace {

/// Draws the requested overlays of frame `f` over `r`.
void draw_overlays(const PreviewOptions& options, const Sequence& sequence, int f, RenderResult& r) {
  const auto& found = sequence.frames();
  const auto it = std::find(found.begin(), found.end(), f);
  if (it == found.end()) throw InputError(sequence.path_of(f), "input frame not found (needed by --overlay)");
  auto frame_mesh = std::make_shared<const FrameMesh>(sequence.load(static_cast<std::size_t>(it - found.begin())));
  Canvas canvas{r.color, r.gbuffer, r.camera, default_depth_bias(frame_mesh->positions)};
  if (options.borders || options.states) {
    const Tracker tracker = Tracker::load(state_path(options.run_dir, f), frame_mesh);
    if (options.borders) draw_patch_borders(canvas, tracker.patches());
    if (options.states) draw_disk_states(canvas, tracker.patches(), std::max(3.0, r.camera.width / 150.0));
  }
  if (options.velocity)
    draw_velocities(canvas, *frame_mesh, options.velocity_scale / sequence.fps(), options.arrow_spacing);
}

}  // namespace

PreviewSummary run_preview(const PreviewOptions& given) {
  // The run's job.toml says where its files are and what it read; what is
  // given here wins.
  PreviewOptions options = given;
  std::optional<JobOptions> job;
  if (std::filesystem::exists(job_record_path(options.run_dir))) {
    job = read_job_manifest(options.run_dir);
    job->output.dir = options.run_dir;
    if (options.input.pattern.empty()) options.input = job->input;
  }
  options.validate();
  const std::string mesh_pattern = !options.mesh_pattern.empty() ? options.mesh_pattern
                                   : job                         ? job->output.mesh()
                                                                 : options.run_dir + "/mesh.####.obj";
  const FramePattern meshes(mesh_pattern);
  const FramePattern atlases(!options.atlas_pattern.empty() ? options.atlas_pattern
                             : job                          ? job->output.atlas()
                                                            : options.run_dir + "/atlas.####.exr");
  const std::vector<int> frames = options.frames.empty() ? meshes.discover() : parse_frame_range(options.frames);
  if (frames.empty()) throw InputError(mesh_pattern, "no frame matches this pattern");
  // The overlays read the input as run did: every frame on disk (central
  // differences with --velocity-from-positions see the same neighbours).
  std::optional<Sequence> sequence;
  if (options.overlays()) sequence.emplace(options.input);
  const FramePattern out(options.run_dir + "/preview/frame.####.png");
  std::vector<Image> sheet;
  std::vector<std::string> labels;
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const int f = frames[j];
    RenderResult r = render(read_uv_mesh(meshes.path(f)), read_image(atlases.path(f), kMaxAtlasPixels), options.render);
    if (sequence) draw_overlays(options, *sequence, f, r);
    if (!options.sheet_only) write_image(out.path(f), r.color);
    if (options.sheet > 0 && j % static_cast<std::size_t>(options.sheet) == 0) {
      sheet.push_back(std::move(r.color));
      labels.push_back(std::to_string(f));
    }
  }
  PreviewSummary summary;
  summary.frames = frames.size();
  if (!options.sheet_only) summary.frame_pattern = out.pattern();
  if (options.sheet > 0) {
    summary.sheet_path = options.run_dir + "/preview/sheet.png";
    summary.sheet_frames = sheet.size();
    write_image(summary.sheet_path, contact_sheet(sheet, labels));
  }
  return summary;
}

}  // namespace fluidtex
