#include "fluidtex/io/vdb_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <mutex>

#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/File.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/parallel_for.h>

#include "fluidtex/geometry/level_set.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

const std::vector<std::string>& default_vdb_velocity_names() {
  static const std::vector<std::string> names = {"vel", "velocity", "v"};
  return names;
}

namespace {

/// Text from the file or from OpenVDB made fit for a one-line error:
/// control characters and bytes outside ASCII become '?', at most 200.
std::string printable(const std::string& text) {
  std::string s = text.substr(0, 200);
  for (char& c : s) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return s;
}

/// Walks the file's header and grid descriptors (OpenVDB file format >= 222:
/// magic, versions, offsets flag, UUID, file metadata, then per grid its
/// name, type, instance parent and the byte offsets of its data) and checks
/// that every grid lies inside the file. OpenVDB seeks to those offsets
/// without checking them: on a truncated cache it reads past the end and
/// can loop or crash instead of failing.
/// Reads the fields of a VDB file's header, every size checked against the
/// file's: InputError naming the file for one that runs past its end.
class VdbHeaderReader {
 public:
  explicit VdbHeaderReader(const std::string& path)
      : path_(path), in_(path, std::ios::binary), size_(static_cast<std::int64_t>(std::filesystem::file_size(path))) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "not a readable OpenVDB file (" + what + ")");
  }
  template <class T>
  void read(T& value) {
    if (!in_.read(reinterpret_cast<char*>(&value), sizeof value)) fail("truncated or damaged header");
  }
  void skip(std::int64_t bytes) {
    if (bytes < 0 || bytes > size_ - position()) fail("truncated or damaged header");
    in_.seekg(bytes, std::ios::cur);
  }
  std::string read_string() {
    std::uint32_t length = 0;
    read(length);
    if (length > size_ - position()) fail("truncated or damaged header");
    std::string text(length, '\0');
    in_.read(text.data(), length);
    return text;
  }
  /// A metadata map: a count, then per entry name, type and sized value.
  void skip_metadata() {
    std::uint32_t entries = 0;
    read(entries);
    for (std::uint32_t e = 0; e < entries; ++e) {
      read_string(), read_string();
      std::uint32_t bytes = 0;
      read(bytes);
      skip(bytes);
    }
  }
  std::int64_t position() { return std::int64_t(in_.tellg()); }
  void seek(std::int64_t pos) { in_.seekg(pos); }
  std::int64_t size() const { return size_; }

 private:
  std::string path_;
  std::ifstream in_;
  std::int64_t size_;
};

void check_layout(const std::string& path) {
  VdbHeaderReader in(path);
  const std::int64_t size = in.size();
  std::int64_t magic = 0;
  std::uint32_t version = 0, major = 0, minor = 0;
  char offsets = 0;
  in.read(magic);
  if (magic != 0x56444220) in.fail("not a VDB file");
  in.read(version);
  if (version < 222) return;  // older layouts: left to OpenVDB
  in.read(major), in.read(minor), in.read(offsets);
  if (!offsets) return;  // written as a stream: no offsets to check
  in.skip(36);           // UUID
  in.skip_metadata();
  std::int32_t grids = 0;
  in.read(grids);
  for (std::int32_t g = 0; g < grids; ++g) {
    const std::string name = in.read_string();
    in.read_string(), in.read_string();  // type, instance parent
    std::int64_t grid_pos = 0, block_pos = 0, end_pos = 0;
    in.read(grid_pos), in.read(block_pos), in.read(end_pos);
    if (!(grid_pos <= block_pos && block_pos <= end_pos && end_pos <= size && grid_pos >= in.position())) {
      in.fail("truncated: grid '" + printable(openvdb::io::GridDescriptor::nameAsString(name)) + "' spans bytes " +
              std::to_string(grid_pos) + "-" + std::to_string(end_pos) + " of a " + std::to_string(size) +
              "-byte file");
    }
    // The grid's own metadata (after its compression flags) and the name of
    // its transform: OpenVDB allocates what a size field says before
    // reading it.
    in.seek(grid_pos + 4);
    in.skip_metadata();
    in.read_string();  // the transform's type
    if (in.position() > block_pos)
      in.fail("grid '" + printable(openvdb::io::GridDescriptor::nameAsString(name)) + "': metadata runs past its data");
    in.seek(end_pos);
  }
}

/// OpenVDB set up for reading untrusted files. Frames are read whole (no
/// delayed loading), so the per-grid delayed-load index ("file_delayed_load"
/// metadata) is never used; unregistering its type makes OpenVDB keep it
/// as opaque bytes instead of parsing it, so that a damaged index cannot make
/// it allocate or loop on the sizes it holds.
void initialize_reader() {
  static std::once_flag once;
  initialize_openvdb();
  std::call_once(once, [] { openvdb::io::DelayedLoadMetadata::unregisterType(); });
}

/// An open .vdb file (opening reads the grid descriptors); grids are read
/// one at a time, each whole, and only when asked for.
class VdbFile {
 public:
  explicit VdbFile(const std::string& path) : path_(path), file_(path) {
    require_regular_file(path, "VDB file");
    initialize_reader();
    check_layout(path);
    try {
      file_.open(false);  // no delayed loading: a bad block fails in readGrid, not deep inside a tool
    } catch (const std::exception& e) {
      throw InputError(path, "not a readable OpenVDB file (" + printable(e.what()) + ")");
    }
    for (auto it = file_.beginName(); it != file_.endName(); ++it) names_.push_back(*it);
    std::sort(names_.begin(), names_.end());
  }

  const std::string& path() const { return path_; }
  bool has(const std::string& name) const { return std::find(names_.begin(), names_.end(), name) != names_.end(); }

  /// "a, b, c" (or "none") for error messages.
  std::string listing() const {
    std::string text;
    for (const std::string& n : names_) text += (text.empty() ? "'" : ", '") + printable(n) + "'";
    return text.empty() ? "none" : text;
  }
  const std::vector<std::string>& names() const { return names_; }

  /// The grid's metadata and transform, without its voxels; null when
  /// OpenVDB cannot read even that (a grid type it does not know).
  openvdb::GridBase::Ptr metadata(const std::string& name) {
    try {
      return file_.readGridMetadata(name);
    } catch (const std::exception&) {
      return nullptr;
    }
  }

  /// metadata(), or an InputError when it cannot be read.
  openvdb::GridBase::Ptr required_metadata(const std::string& name) {
    openvdb::GridBase::Ptr meta = metadata(name);
    if (!meta) {
      throw InputError(path_, "grid '" + printable(name) +
                                  "' cannot be read (a grid type this OpenVDB does not know, or a damaged header)");
    }
    return meta;
  }

  openvdb::GridBase::Ptr grid(const std::string& name) {
    try {
      return file_.readGrid(name);
    } catch (const std::exception& e) {
      throw InputError(path_, "cannot read grid '" + printable(name) + "' (" + printable(e.what()) + ")");
    }
  }

  void require(const std::string& name, const std::string& option) const {
    if (!has(name))
      throw InputError(path_,
                       "no grid '" + printable(name) + "' (" + option + "; grids in the file: " + listing() + ")");
  }

 private:
  std::string path_;
  openvdb::io::File file_;
  std::vector<std::string> names_;
};

/// The level-set grid: the named one, else the first level set by name, else
/// `surface` or `phi`.
std::string find_surface(VdbFile& file, const VdbReadOptions& options) {
  if (!options.surface.empty()) {
    file.require(options.surface, "--vdb-surface");
    return options.surface;
  }
  for (const std::string& name : file.names()) {
    openvdb::GridBase::Ptr meta = file.metadata(name);
    if (meta && meta->getGridClass() == openvdb::GRID_LEVEL_SET) return name;
  }
  for (const char* name : {"surface", "phi"}) {
    if (file.has(name)) return name;
  }
  // Blender's Mantaflow data cache: a staggered `velocity` next to a
  // `particles` point grid, and no surface at all.
  const bool mantaflow = file.has("particles") && file.has("velocity");
  throw InputError(file.path(),
                   "no level-set grid (looked for a grid of class level set, or one named 'surface' or "
                   "'phi'; grids in the file: " +
                       file.listing() + "); name it with --vdb-surface" +
                       (mantaflow ? " (Blender's Mantaflow data cache holds no surface: export the "
                                    "liquid with scripts/blender/export_fluid.py, see docs/dcc.md)"
                                  : ""));
}

openvdb::FloatGrid::Ptr read_surface(VdbFile& file, const std::string& name) {
  const openvdb::GridBase::Ptr meta = file.required_metadata(name);
  if (!meta->isType<openvdb::FloatGrid>()) {
    throw InputError(file.path(), "grid '" + printable(name) + "' holds " + printable(meta->valueType()) +
                                      " values; a level set holds float signed distances");
  }
  if (meta->getGridClass() == openvdb::GRID_FOG_VOLUME) {
    throw InputError(file.path(), "grid '" + printable(name) +
                                      "' is a fog volume (a density), not a level set; convert it to a level set "
                                      "first or name the level set with --vdb-surface");
  }
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.grid(name));
  // A level set is positive outside; a fog volume marked with no class has
  // a background of 0 (or below).
  if (!(grid->background() > 0.0f)) {
    throw InputError(file.path(), "grid '" + printable(name) + "' has background " +
                                      std::to_string(grid->background()) +
                                      ": not a signed distance (a level set is positive outside the liquid)");
  }
  return grid;
}

/// The velocity grid's name: the named one, else the first default present;
/// empty when there is none and none was named.
std::string find_velocity(const VdbFile& file, const VdbReadOptions& options) {
  if (!options.velocity.empty()) {
    file.require(options.velocity, "--vdb-velocity");
    return options.velocity;
  }
  for (const std::string& name : default_vdb_velocity_names()) {
    if (file.has(name)) return name;
  }
  return {};
}

template <class GridT>
std::vector<Vec3> sample(const std::string& path, const std::string& name, const GridT& grid,
                         const std::vector<Vec3>& positions) {
  std::vector<Vec3> out(positions.size(), Vec3::Zero());
  if (grid.activeVoxelCount() == 0) {
    throw InputError(path, "velocity grid '" + printable(name) + "' has no active value");
  }
  const bool staggered = grid.getGridClass() == openvdb::GRID_STAGGERED;
  std::vector<char> covered(positions.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size(), 512), [&](const auto& range) {
    typename GridT::ConstAccessor acc = grid.getConstAccessor();
    const openvdb::tools::GridSampler<typename GridT::ConstAccessor, openvdb::tools::BoxSampler> box(acc,
                                                                                                     grid.transform());
    const openvdb::tools::GridSampler<typename GridT::ConstAccessor, openvdb::tools::StaggeredBoxSampler> staggered_box(
        acc, grid.transform());
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const openvdb::Vec3d p(positions[v].x(), positions[v].y(), positions[v].z());
      const auto value = staggered ? staggered_box.wsSample(p) : box.wsSample(p);
      out[v] = Vec3(value.x(), value.y(), value.z());
      const openvdb::Coord ijk = openvdb::Coord::round(grid.transform().worldToIndex(p));
      covered[v] = acc.isValueOn(ijk) ? 1 : 0;
      if (!out[v].allFinite()) covered[v] = 2;
    }
  });
  if (std::find(covered.begin(), covered.end(), 2) != covered.end()) {
    throw InputError(path, "velocity grid '" + printable(name) + "' has NaN or infinite values at the surface");
  }
  if (!positions.empty() && std::find(covered.begin(), covered.end(), 1) == covered.end()) {
    throw InputError(path, "velocity grid '" + printable(name) +
                               "' has no active value at any surface vertex (a transform that does not match the "
                               "surface's?)");
  }
  return out;
}

std::vector<Vec3> sample_velocity(VdbFile& file, const std::string& name, const std::vector<Vec3>& positions) {
  const openvdb::GridBase::Ptr meta = file.required_metadata(name);
  if (meta->isType<openvdb::Vec3SGrid>()) {
    return sample(file.path(), name, *openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.grid(name)), positions);
  }
  if (meta->isType<openvdb::Vec3DGrid>()) {
    return sample(file.path(), name, *openvdb::gridPtrCast<openvdb::Vec3DGrid>(file.grid(name)), positions);
  }
  throw InputError(file.path(), "velocity grid '" + printable(name) + "' holds " + printable(meta->valueType()) +
                                    " values, not 3-vectors (vec3s or vec3d)");
}

}  // namespace

FrameMesh read_vdb_frame(const std::string& path, const VdbReadOptions& options, bool require_velocities) {
  VdbFile file(path);
  const std::string surface = find_surface(file, options);
  const std::string velocity = find_velocity(file, options);
  if (velocity.empty() && require_velocities) {
    throw InputError(path, "no velocity grid (looked for 'vel', 'velocity', 'v'; grids in the file: " + file.listing() +
                               "); name it with --vdb-velocity");
  }
  FrameMesh mesh = mesh_level_set(*read_surface(file, surface), options.iso, options.adaptivity);
  if (mesh.triangles.empty()) {
    throw InputError(path, "empty mesh: level set '" + printable(surface) + "' has no surface at iso value " +
                               std::to_string(options.iso));
  }
  if (!velocity.empty()) mesh.velocities = sample_velocity(file, velocity, mesh.positions);
  return mesh;
}

std::vector<Vec3> read_vdb_velocities(const std::string& path, const VdbReadOptions& options,
                                      const std::vector<Vec3>& positions) {
  VdbFile file(path);
  const std::string velocity = find_velocity(file, options);
  if (velocity.empty()) {
    throw InputError(path, "no velocity grid (looked for 'vel', 'velocity', 'v'; grids in the file: " + file.listing() +
                               "); name it with --vdb-velocity");
  }
  return sample_velocity(file, velocity, positions);
}

void write_vdb_frame(const std::string& path, const FrameMesh& mesh, const VdbWriteOptions& options) {
  initialize_openvdb();
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(options.voxel_size);
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) {
    points.emplace_back(xform->worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z())));
  }
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const Tri& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  const float band = static_cast<float>(options.half_width);
  openvdb::FloatGrid::Ptr surface = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I>(points, triangles), *xform, band,
      band);
  surface->setName(options.surface);
  surface->setGridClass(openvdb::GRID_LEVEL_SET);

  // Velocity over the level set's band: that of the closest surface point
  // (an exact query, so the grid does not depend on the thread schedule).
  const SurfaceIndex index(mesh);
  openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  velocity->setTransform(xform);
  velocity->setName(options.velocity);
  velocity->setGridClass(options.staggered ? openvdb::GRID_STAGGERED : openvdb::GRID_UNKNOWN);
  velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
  velocity->tree().topologyUnion(surface->tree());
  std::vector<openvdb::Vec3SGrid::TreeType::LeafNodeType*> leaves;
  velocity->tree().getNodes(leaves);
  auto velocity_at = [&](const openvdb::Vec3d& ijk) {
    const openvdb::Vec3d w = xform->indexToWorld(ijk);
    return index.velocity_at(index.closest_point(Vec3(w.x(), w.y(), w.z())));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    for (std::size_t l = range.begin(); l != range.end(); ++l) {
      for (auto it = leaves[l]->beginValueOn(); it; ++it) {
        const openvdb::Vec3d ijk = it.getCoord().asVec3d();
        Vec3 v;
        if (options.staggered) {
          for (int k = 0; k < 3; ++k) {
            openvdb::Vec3d face = ijk;
            face[k] -= 0.5;
            v[k] = velocity_at(face)[k];
          }
        } else {
          v = velocity_at(ijk);
        }
        it.setValue(openvdb::Vec3s(float(v.x()), float(v.y()), float(v.z())));
      }
    }
  });
  if (surface->activeVoxelCount() == 0) throw InternalError(path + ": the mesh gave an empty level set");

  write_atomically(path, [&](const std::filesystem::path& tmp) {
    openvdb::io::File file(tmp.string());
    file.write(openvdb::GridCPtrVec{surface, velocity});
    file.close();
  });
}

}  // namespace fluidtex
