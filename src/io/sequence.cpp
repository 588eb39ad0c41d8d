#include "fluidtex/io/sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/mesh_io.h"
#include "fluidtex/io/vdb_io.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

void InputOptions::validate() const {
  if (pattern.empty()) throw InputError("", "-i/--input: an input frame pattern is required");
  if (pattern.find(kUdimToken) != std::string::npos)
    throw InputError(pattern, "-i/--input: <UDIM> names the tiles of a texture, not of a mesh");
  check_options(*this);
  if (!velocity_vdb.empty() && velocity_from_positions) {
    throw InputError("", "--velocity-vdb and --velocity-from-positions both give the velocities: choose one");
  }
}

Sequence::Sequence(const InputOptions& options) : options_(options), pattern_(options.pattern) {
  options_.validate();
  if (!options_.frames.empty()) {
    frames_ = parse_frame_range(options_.frames);
    for (int f : frames_) {
      std::error_code ec;
      if (!std::filesystem::exists(std::filesystem::symlink_status(pattern_.path(f), ec))) {
        throw InputError(pattern_.path(f),
                         "missing frame " + std::to_string(f) + " of the requested range " + options_.frames);
      }
    }
  } else {
    frames_ = pattern_.discover();
    if (frames_.empty()) throw InputError(options_.pattern, "no frame matches this pattern");
  }
  // Every frame is a regular file, checked before any output is written (a
  // folder or FIFO named like a frame is an error, never a skipped frame).
  for (int f : frames_) require_regular_file(pattern_.path(f), "frame " + std::to_string(f));
  if (!options_.velocity_vdb.empty()) {
    velocity_pattern_.emplace(options_.velocity_vdb);
    for (int f : frames_)
      require_regular_file(velocity_pattern_->path(f), "velocity VDB of frame " + std::to_string(f));
  }
  stated_fps_ = read_stated_fps(pattern_.path(frames_.front()));
  if (!options_.fps) {
    options_.fps = stated_fps_.value_or(kDefaultFps);
    fps_source_ = stated_fps_ ? FpsSource::Header : FpsSource::Default;
  }
}

std::vector<int> Sequence::followed_frames() const {
  if (options_.skipped_frames == SkippedFrames::Ignore || frames_.size() < 2) return frames_;
  std::vector<int> on_disk = pattern_.discover();
  std::erase_if(on_disk, [&](int f) {
    std::error_code ec;
    return !std::filesystem::is_regular_file(pattern_.path(f), ec) ||
           (velocity_pattern_ && !std::filesystem::is_regular_file(velocity_pattern_->path(f), ec));
  });
  std::vector<int> followed;
  followed.reserve(frames_.size());
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    followed.push_back(frames_[i]);
    if (i + 1 == frames_.size()) break;
    auto between = std::upper_bound(on_disk.begin(), on_disk.end(), frames_[i]);
    for (; between != on_disk.end() && *between < frames_[i + 1]; ++between) followed.push_back(*between);
  }
  return followed;
}

Sequence Sequence::followed() const {
  const std::vector<int> frames = followed_frames();
  if (frames.size() == frames_.size()) return *this;
  InputOptions input = options_;
  input.frames = format_frame_range(frames);
  Sequence sequence(input);
  sequence.fps_source_ = fps_source_;  // input.fps holds this sequence's rate, given or not
  return sequence;
}

namespace {

/// --velocity-from-positions reads vertex i of two frames as one point of
/// the fluid. A remeshed sequence can keep its vertex count and still
/// number its vertices anew: its "velocities" are then jumps across the
/// surface. Between frames that correspond, an edge's two ends move almost
/// alike (it stretches by a fraction of its length per frame); after a
/// renumbering its ends land anywhere. So the median over the edges of
/// |Δ(b − a)| / |b − a| is small for a real sequence and far above 1 for a
/// renumbered one: above 1 (the median edge changing by its own length in
/// one step), the sequence is refused.
void check_correspondence(const FrameMesh& mesh, const std::vector<Vec3>& other, const std::string& path,
                          const std::string& other_path) {
  std::vector<double> change;
  change.reserve(mesh.triangles.size() * 3);
  for (const Tri& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const double length = (mesh.positions[b] - mesh.positions[a]).norm();
      if (!(length > 0.0)) continue;
      change.push_back(((other[b] - other[a]) - (mesh.positions[b] - mesh.positions[a])).norm() / length);
    }
  }
  if (change.empty()) return;
  auto mid = change.begin() + static_cast<std::ptrdiff_t>(change.size() / 2);
  std::nth_element(change.begin(), mid, change.end());
  if (*mid <= 1.0) return;
  char ratio[32];
  std::snprintf(ratio, sizeof ratio, "%.3g", *mid);
  throw InputError(other_path, std::string("--velocity-from-positions: its vertices do not correspond to ") + path +
                                   "'s (the median edge changes by " + ratio +
                                   " edge lengths between them: a remeshed sequence that only keeps its vertex "
                                   "count); take the velocities from the files instead");
}

}  // namespace

FrameMesh Sequence::load(std::size_t index, CleanReport* report) const {
  const int frame = frames_.at(index);
  const std::string path = pattern_.path(frame);
  ReadOptions read;
  read.velocity_attr = options_.velocity_attr;
  read.require_velocities = !options_.velocity_from_positions && !velocity_pattern_;
  read.vdb = {.surface = options_.vdb_surface,
              .velocity = options_.vdb_velocity,
              .iso = options_.vdb_iso,
              .adaptivity = options_.vdb_adaptivity};
  read.clean = false;  // cleaning renumbers vertices: derive velocities first
  FrameMesh mesh = read_frame(path, read);
  if (velocity_pattern_)
    mesh.velocities = read_vdb_velocities(velocity_pattern_->path(frame), read.vdb, mesh.positions);

  if (options_.velocity_from_positions && frames_.size() > 1) {
    const std::size_t lo = index > 0 ? index - 1 : index;
    const std::size_t hi = index + 1 < frames_.size() ? index + 1 : index;
    auto positions_of = [&](std::size_t i) {
      if (i == index) return mesh.positions;
      FrameMesh other = read_frame(pattern_.path(frames_[i]), read);
      if (other.positions.size() != mesh.positions.size()) {
        throw InputError(pattern_.path(frames_[i]),
                         "has " + std::to_string(other.positions.size()) + " vertices but " + path + " has " +
                             std::to_string(mesh.positions.size()) +
                             ": --velocity-from-positions needs a constant vertex count and order");
      }
      check_correspondence(mesh, other.positions, path, pattern_.path(frames_[i]));
      return std::move(other.positions);
    };
    const std::vector<Vec3> before = positions_of(lo);
    const std::vector<Vec3> after = positions_of(hi);
    const double seconds = static_cast<double>(frames_[hi] - frames_[lo]) / fps();
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      mesh.velocities[v] = (after[v] - before[v]) / seconds;
    }
  }

  CleanReport cleaned = clean_frame(path, mesh);
  if (options_.strict && cleaned.nonmanifold_edges > 0) {
    throw InputError(
        path, std::to_string(cleaned.nonmanifold_edges) + " non-manifold edges (--strict rejects non-manifold frames)");
  }
  if (report) *report = cleaned;
  return mesh;
}

}  // namespace fluidtex
