// Tests of vdb_io: OpenVDB level set + velocity frames. The files are built
// here with OpenVDB itself: a sphere level set and a linear velocity field,
// which trilinear interpolation reproduces exactly, so a sampling mistake
// (a staggered grid read as collocated, a transform ignored) shows as an
// error far above the tolerance.

#include <gtest/gtest.h>

#include <openvdb/io/File.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <numeric>

#include "fluidtex/geometry/level_set.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/io/mesh_io.h"
#include "fluidtex/io/sequence.h"
#include "fluidtex/io/vdb_io.h"
#include "fluidtex/scenes/scenes.h"
#include "fluidtex/util/error.h"
#include "test_util.h"

namespace fluidtex {
namespace {

using test::TempDir;

const Vec3 kCentre(0.3, -0.2, 0.5);
constexpr double kRadius = 0.4;

/// A linear field: translation, rotation about kCentre and a stretch along
/// the axes (so that each component changes along its own axis, and a
/// staggered grid read as collocated is off by half a voxel's worth).
Vec3 linear_field(const Vec3& p) {
  const Vec3 r = p - kCentre;
  return Vec3(0.1, 0.2, -0.3) + Vec3(0.5, -1.0, 2.0).cross(r) + Vec3(0.7 * r.x(), -0.3 * r.y(), -0.4 * r.z());
}

openvdb::FloatGrid::Ptr sphere(double voxel, const std::string& name = "surface") {
  initialize_openvdb();
  auto grid = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
      float(kRadius), openvdb::Vec3f(float(kCentre.x()), float(kCentre.y()), float(kCentre.z())), float(voxel));
  grid->setName(name);
  return grid;
}

/// The rigid field on a grid with `transform`, over the box around the
/// sphere; staggered: component k at the face ijk - e_k / 2.
openvdb::Vec3SGrid::Ptr velocity_grid(const openvdb::math::Transform::Ptr& transform, bool staggered,
                                      const std::string& name = "vel") {
  auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  grid->setTransform(transform);
  grid->setName(name);
  if (staggered) grid->setGridClass(openvdb::GRID_STAGGERED);
  const openvdb::Vec3d lo = transform->worldToIndex(openvdb::Vec3d(-0.2, -0.7, 0.0));
  const openvdb::Vec3d hi = transform->worldToIndex(openvdb::Vec3d(0.8, 0.3, 1.0));
  auto acc = grid->getAccessor();
  for (int i = int(std::floor(lo.x())); i <= int(std::ceil(hi.x())); ++i) {
    for (int j = int(std::floor(lo.y())); j <= int(std::ceil(hi.y())); ++j) {
      for (int k = int(std::floor(lo.z())); k <= int(std::ceil(hi.z())); ++k) {
        Vec3 v;
        for (int c = 0; c < 3; ++c) {
          openvdb::Vec3d ijk(i, j, k);
          if (staggered) ijk[c] -= 0.5;
          const openvdb::Vec3d w = transform->indexToWorld(ijk);
          v[c] = linear_field(Vec3(w.x(), w.y(), w.z()))[c];
        }
        acc.setValue(openvdb::Coord(i, j, k), openvdb::Vec3s(float(v.x()), float(v.y()), float(v.z())));
      }
    }
  }
  return grid;
}

void write_grids(const std::string& path, const openvdb::GridPtrVec& grids) {
  openvdb::io::File file(path);
  file.write(grids);
  file.close();
}

/// Largest |velocity - rigid| and |distance to centre - radius| over the mesh.
void expect_sphere_with_linear_velocity(const FrameMesh& mesh, double voxel, double velocity_tolerance) {
  ASSERT_GT(mesh.triangles.size(), 100u);
  double surface_error = 0.0, velocity_error = 0.0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    surface_error = std::max(surface_error, std::abs((mesh.positions[v] - kCentre).norm() - kRadius));
    velocity_error = std::max(velocity_error, (mesh.velocities[v] - linear_field(mesh.positions[v])).norm());
  }
  EXPECT_LT(surface_error, 0.1 * voxel);
  EXPECT_LT(velocity_error, velocity_tolerance);
  // Outward triangles: positive enclosed volume, about the sphere's.
  double volume6 = 0.0;
  for (const Tri& t : mesh.triangles) {
    volume6 += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
  }
  EXPECT_NEAR(volume6 / 6.0, 4.0 / 3.0 * M_PI * std::pow(kRadius, 3), 0.01);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(VdbIo, LevelSetWithCollocatedVelocity) {
  TempDir dir;
  const double voxel = 0.02;
  auto surface = sphere(voxel);
  write_grids(dir.file("f.vdb"), {surface, velocity_grid(surface->transformPtr(), false)});
  const FrameMesh mesh = read_frame(dir.file("f.vdb"));
  // A rigid field is linear: trilinear interpolation returns it to float
  // precision (reading the grid as staggered would be off by |w| voxel / 2).
  expect_sphere_with_linear_velocity(mesh, voxel, 1e-4);
}

TEST(VdbIo, StaggeredVelocityIsSampledOnTheFaces) {
  TempDir dir;
  const double voxel = 0.02;
  auto surface = sphere(voxel);
  write_grids(dir.file("f.vdb"), {surface, velocity_grid(surface->transformPtr(), true, "velocity")});
  expect_sphere_with_linear_velocity(read_frame(dir.file("f.vdb")), voxel, 1e-4);

  // The same values marked collocated are read half a voxel off: the test
  // can tell the two apart.
  auto mislabelled = velocity_grid(surface->transformPtr(), true, "velocity");
  mislabelled->setGridClass(openvdb::GRID_UNKNOWN);
  write_grids(dir.file("g.vdb"), {surface, mislabelled});
  const FrameMesh wrong = read_frame(dir.file("g.vdb"));
  double error = 0.0;
  for (std::size_t v = 0; v < wrong.positions.size(); ++v) {
    error = std::max(error, (wrong.velocities[v] - linear_field(wrong.positions[v])).norm());
  }
  EXPECT_GT(error, 0.003);  // 0.7 * voxel / 2
}

TEST(VdbIo, EachGridKeepsItsOwnTransform) {
  TempDir dir;
  const double voxel = 0.025;
  // The level set in a translated frame, the velocity on a coarser grid
  // with another offset: both are sampled in world space.
  auto surface = sphere(voxel);
  auto shifted = openvdb::math::Transform::createLinearTransform(0.04);
  shifted->postTranslate(openvdb::Vec3d(0.013, -0.007, 0.021));
  write_grids(dir.file("f.vdb"), {surface, velocity_grid(shifted, true)});
  expect_sphere_with_linear_velocity(read_frame(dir.file("f.vdb")), voxel, 1e-4);

  auto level_set_transform = openvdb::math::Transform::createLinearTransform(voxel);
  level_set_transform->postTranslate(openvdb::Vec3d(0.5, 0.25, -0.125));
  // The sphere sampled on a translated index lattice.
  auto translated = openvdb::FloatGrid::create(float(3 * voxel));
  translated->setTransform(level_set_transform);
  translated->setGridClass(openvdb::GRID_LEVEL_SET);
  translated->setName("surface");
  {
    auto acc = translated->getAccessor();
    const openvdb::Vec3d c = level_set_transform->worldToIndex(openvdb::Vec3d(kCentre.x(), kCentre.y(), kCentre.z()));
    const double r = kRadius / voxel;
    for (int i = int(c.x() - r - 4); i <= int(c.x() + r + 4); ++i) {
      for (int j = int(c.y() - r - 4); j <= int(c.y() + r + 4); ++j) {
        for (int k = int(c.z() - r - 4); k <= int(c.z() + r + 4); ++k) {
          const double d = ((openvdb::Vec3d(i, j, k) - c).length() - r) * voxel;
          if (std::abs(d) < 3 * voxel) acc.setValue(openvdb::Coord(i, j, k), float(d));
        }
      }
    }
  }
  openvdb::tools::signedFloodFill(translated->tree());
  write_grids(dir.file("g.vdb"), {translated, velocity_grid(shifted, false)});
  expect_sphere_with_linear_velocity(read_frame(dir.file("g.vdb")), voxel, 1e-4);
}

TEST(VdbIo, FindsTheLevelSetByClassOrName) {
  TempDir dir;
  auto surface = sphere(0.03, "liquid");
  auto density = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
  write_grids(dir.file("f.vdb"), {density, surface, velocity_grid(surface->transformPtr(), false, "v")});
  EXPECT_GT(read_frame(dir.file("f.vdb")).triangles.size(), 100u);

  // Mantaflow's `phi` carries no class: found by its name.
  auto phi = sphere(0.03, "phi");
  phi->setGridClass(openvdb::GRID_UNKNOWN);
  write_grids(dir.file("g.vdb"), {density, phi, velocity_grid(phi->transformPtr(), false)});
  EXPECT_GT(read_frame(dir.file("g.vdb")).triangles.size(), 100u);
}

TEST(VdbIo, ReadsOnlyTheGridsItNeeds) {
  // A particle grid whose attribute type this process cannot load (as
  // Blender's Mantaflow cache holds) sits next to the surface and velocity.
  TempDir dir;
  auto surface = sphere(0.03);
  const std::vector<openvdb::Vec3R> positions = {{0, 0, 0}, {0.1, 0.1, 0.1}};
  auto points = openvdb::points::createPointDataGrid<openvdb::points::NullCodec, openvdb::points::PointDataGrid>(
      positions, *openvdb::math::Transform::createLinearTransform(0.1));
  points->setName("pp");
  write_grids(dir.file("f.vdb"), {points, surface, velocity_grid(surface->transformPtr(), false)});
  using Position = openvdb::points::TypedAttributeArray<openvdb::Vec3f, openvdb::points::NullCodec>;
  Position::unregisterType();
  // Reading every grid fails now, as it does on such a cache...
  bool whole_file_fails = false;
  try {
    openvdb::io::File file(dir.file("f.vdb"));
    file.open();
    file.getGrids();
  } catch (const std::exception&) {
    whole_file_fails = true;
  }
  // ...but the frame reads.
  std::string error;
  FrameMesh mesh;
  try {
    mesh = read_frame(dir.file("f.vdb"));
  } catch (const std::exception& e) {
    error = e.what();
  }
  Position::registerType();
  EXPECT_TRUE(whole_file_fails);
  EXPECT_EQ(error, "");
  EXPECT_GT(mesh.triangles.size(), 100u);
}

TEST(VdbIo, BadGridsAreOneLineErrorsNamingTheFile) {
  TempDir dir;
  auto surface = sphere(0.03);
  const auto transform = surface->transformPtr();
  const std::string path = dir.file("f.vdb");
  auto expect_error = [&](const openvdb::GridPtrVec& grids, const std::string& fragment,
                          const VdbReadOptions& options = {}) {
    write_grids(path, grids);
    const std::string message = error_of([&] { read_vdb_frame(path, options, true); });
    EXPECT_NE(message.find(path + ": "), std::string::npos) << fragment << ": " << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << fragment << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  // No velocity grid, a named one missing, a surface named but missing.
  expect_error({surface}, "no velocity grid");
  expect_error({surface, velocity_grid(transform, false)}, "no grid 'flow'", {.velocity = "flow"});
  expect_error({surface, velocity_grid(transform, false)}, "no grid 'sdf'", {.surface = "sdf"});
  // No level set at all.
  auto density = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
  expect_error({density, velocity_grid(transform, false)}, "no level-set grid");
  // Blender's Mantaflow data cache (a staggered `velocity`, a `particles`
  // grid, no surface): the error says what to do instead.
  auto particles = openvdb::FloatGrid::create(0.0f);
  particles->setName("particles");
  expect_error({particles, velocity_grid(transform, true, "velocity")}, "scripts/blender/export_fluid.py");
  // A fog volume where a level set was asked for.
  expect_error({density, velocity_grid(transform, false)}, "fog volume", {.surface = "density"});
  // A grid with no class and a zero background is no signed distance.
  density->setGridClass(openvdb::GRID_UNKNOWN);
  expect_error({density, velocity_grid(transform, false)}, "not a signed distance", {.surface = "density"});
  // A velocity that is not a vector.
  auto speed = openvdb::FloatGrid::create(0.0f);
  speed->setName("vel");
  speed->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
  expect_error({surface, speed}, "not 3-vectors");
  // A level set that is not float.
  auto int_grid = openvdb::Int32Grid::create(1);
  int_grid->setName("surface");
  expect_error({int_grid, velocity_grid(transform, false)}, "a level set holds float");
  // A velocity grid that is nowhere near the surface.
  auto far = openvdb::math::Transform::createLinearTransform(0.03);
  far->postTranslate(openvdb::Vec3d(100, 0, 0));
  auto elsewhere = velocity_grid(transform, false);
  elsewhere->setTransform(far);
  expect_error({surface, elsewhere}, "no active value at any surface vertex");
  // A velocity grid with NaN at the surface.
  auto nan = velocity_grid(transform, false);
  nan->tree().fill(nan->evalActiveVoxelBoundingBox(), openvdb::Vec3s(std::nanf(""), 0.0f, 0.0f));
  expect_error({surface, nan}, "NaN");

  // Not a VDB file, a truncated one.
  test::write_file(path, "not a vdb file at all");
  EXPECT_NE(error_of([&] { read_frame(path); }).find("not a readable OpenVDB file"), std::string::npos);
  write_grids(path, {surface, velocity_grid(transform, false)});
  std::string bytes = test::read_file(path);
  test::write_file(path, bytes.substr(0, bytes.size() / 2));
  const std::string truncated = error_of([&] { read_frame(path); });
  EXPECT_EQ(truncated.rfind(path + ": ", 0), 0u) << truncated;
}

TEST(VdbIo, VelocitiesFromAVdbSequenceForAMesh) {
  TempDir dir;
  auto surface = sphere(0.03);
  const FrameMesh meshed = mesh_level_set(*surface);
  write_frame_ply(dir.file("m.0001.ply"), meshed);  // velocities zero
  write_grids(dir.file("v.0001.vdb"), {velocity_grid(surface->transformPtr(), true)});
  InputOptions input;
  input.pattern = dir.file("m.####.ply");
  input.velocity_vdb = dir.file("v.####.vdb");
  const FrameMesh mesh = Sequence(input).load(0);
  expect_sphere_with_linear_velocity(mesh, 0.03, 1e-4);

  // A frame without its VDB is refused before anything is read.
  write_frame_ply(dir.file("m.0002.ply"), meshed);
  const std::string missing = error_of([&] { Sequence{input}; });
  EXPECT_NE(missing.find("v.0002.vdb"), std::string::npos) << missing;
  input.velocity_from_positions = true;
  EXPECT_NE(error_of([&] { input.validate(); }).find("choose one"), std::string::npos);
}

TEST(VdbIo, GeneratedDropAsVdbIsCloseToItsPly) {
  // gen drop --format vdb: the PLY frame voxelised at the scene's own voxel
  // size and meshed again. The surfaces agree to a fraction of a voxel and
  // the velocities to a few percent of the largest speed (the velocity grid
  // holds the closest surface point's velocity, trilinearly blended).
  TempDir dir;
  SceneOptions scene;
  scene.frames = 14;
  scene.resolution = 32;
  write_scene("drop", dir.str(), scene);
  const double drop_voxel = 2.2 / scene.resolution;
  for (bool staggered : {false, true}) {
    SceneOptions vdb = scene;
    vdb.format = "vdb";
    vdb.staggered = staggered;
    write_scene("drop", dir.str(), vdb);
    // Falling, and merged (at contact, frame 8, the scene's velocity changes
    // across the thin gap between drop and pool within a voxel, and the
    // grid cannot hold that: p99 0.13-0.18 there).
    for (int frame : {4, 14}) {
      char name[64];
      std::snprintf(name, sizeof name, "drop.%04d", frame);
      const FrameMesh ply = read_frame(dir.file(std::string(name) + ".ply"));
      const FrameMesh from_vdb = read_frame(dir.file(std::string(name) + ".vdb"));
      const SurfaceIndex index(ply);
      double distance = 0.0, speed = 0.0;
      std::vector<double> velocity;
      for (const Vec3& v : ply.velocities) speed = std::max(speed, v.norm());
      for (std::size_t v = 0; v < from_vdb.positions.size(); ++v) {
        const SurfacePoint s = index.closest_point(from_vdb.positions[v]);
        distance = std::max(distance, s.distance);
        velocity.push_back((from_vdb.velocities[v] - index.velocity_at(s)).norm() / speed);
      }
      std::sort(velocity.begin(), velocity.end());
      const double mean = std::accumulate(velocity.begin(), velocity.end(), 0.0) / double(velocity.size());
      const double p99 = velocity[velocity.size() * 99 / 100];
      const double voxel = drop_voxel;
      std::cout << "frame " << frame << (staggered ? " staggered" : "") << ": surface within " << distance / voxel
                << " voxel; velocity error over the top speed: mean " << mean << ", p99 " << p99 << ", max "
                << velocity.back() << "\n";
      EXPECT_LT(distance, 0.3 * voxel);
      EXPECT_LT(mean, 0.01);
      EXPECT_LT(p99, 0.05);
    }
  }
  EXPECT_NE(error_of([&] {
              SceneOptions flat = scene;
              flat.format = "vdb";
              write_scene("rotation", dir.str(), flat);
            }).find("flat open sheet"),
            std::string::npos);
}

}  // namespace
}  // namespace fluidtex
