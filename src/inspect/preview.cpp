#include "fluidtex/inspect/preview.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "fluidtex/inspect/overlays.h"
#include "fluidtex/inspect/textured_frame.h"
#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/job/job_record.h"
#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

bool PreviewOptions::overlay(const std::string& name) const {
  return std::find(overlays.begin(), overlays.end(), name) != overlays.end();
}

void PreviewOptions::validate() const {
  if (render.width < 1) throw InputError("", "--width must be at least 1");
  if (render.height < 0) throw InputError("", "--height must be at least 1");
  if (sheet < 0) throw InputError("", "--sheet must be at least 1");
  if (sheet_only && sheet == 0) throw InputError("", "--sheet-only needs --sheet K");
  if (arrow_spacing < 1) throw InputError("", "--arrow-spacing must be at least 1");
  if (!overlays.empty() && input.pattern.empty()) {
    throw InputError(
        "", "--overlay " + overlays.front() +
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
  if (options.overlay("borders") || options.overlay("states")) {
    const Tracker tracker = Tracker::load(state_path(options.run_dir, f), frame_mesh, f);
    if (options.overlay("borders")) draw_patch_borders(canvas, tracker.patches());
    if (options.overlay("states")) draw_disk_states(canvas, tracker.patches(), std::max(3.0, r.camera.width / 150.0));
  }
  if (options.overlay("velocity"))
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
  if (!options.camera.empty()) options.render = with_camera(options.render, options.camera);
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
  if (!options.overlays.empty()) sequence.emplace(options.input);
  const FramePattern out(options.run_dir + "/preview/frame.####.png");
  std::vector<Image> sheet;
  std::vector<std::string> labels;
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const int f = frames[j];
    RenderResult r = render(read_uv_mesh(meshes.path(f)), read_frame_atlas(atlases.pattern(), f), options.render);
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

RenderOptions with_camera(RenderOptions render, const std::string& text) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || !std::isfinite(x)) {
      throw InputError("", "--camera: expected EX,EY,EZ,TX,TY,TZ[,FOV] (numbers), got '" + text + "'");
    }
    v.push_back(x);
    start = comma + 1;
  }
  if (v.size() != 6 && v.size() != 7) {
    throw InputError("", "--camera: expected 6 or 7 numbers EX,EY,EZ,TX,TY,TZ[,FOV], got '" + text + "'");
  }
  render.perspective = true;
  render.eye = Vec3(v[0], v[1], v[2]);
  render.target = Vec3(v[3], v[4], v[5]);
  if (v.size() == 7) render.fov_deg = v[6];
  return render;
}

}  // namespace fluidtex
