#include "fluidtex/tracking/surface_change.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <oneapi/tbb/parallel_for.h>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/parallel.h"

namespace fluidtex {

namespace {

Vec3 centroid(const FrameMesh& mesh, const Tri& t) {
  return (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
}

}  // namespace

namespace {

/// Where each face of `previous` lands: its centroid carried by the mean of
/// its vertex velocities over dt (the tracker's Euler step), then projected
/// onto `next`, with the normal there.
struct Landings {
  std::vector<Vec3> position, normal;
};

Landings land_faces(const SurfaceIndex& previous, const SurfaceIndex& next, double dt) {
  const FrameMesh& from = previous.mesh();
  const std::size_t nf = from.triangles.size();
  Landings landed{std::vector<Vec3>(nf), std::vector<Vec3>(nf)};
  const bool has_velocity = from.velocities.size() == from.positions.size();
  parallel_each(nf, [&](std::size_t f) {
    const Tri& t = from.triangles[f];
    Vec3 v = Vec3::Zero();
    if (has_velocity) v = (from.velocities[t[0]] + from.velocities[t[1]] + from.velocities[t[2]]) / 3.0;
    const Vec3 c = centroid(from, t);
    const SurfacePoint p = next.closest_point(c + v * dt);
    landed.position[f] = p.valid() ? p.position : c;
    landed.normal[f] = p.valid() ? next.normal_at(p) : previous.face_normals()[f];
  });
  return landed;
}

/// The change is a mean over a ball of radius d, so it varies little within
/// a quarter of d: it is evaluated at one face per cell of a d/4 grid and
/// plane (the first face, in face order, whose normal passes the plane test
/// against none of the cell's earlier representatives starts a new one),
/// and every face takes its representative's value. A mesh with edges much
/// shorter than d then costs about as many ball sums as d/4 cells.
struct Representatives {
  std::vector<int> of_face;
  std::vector<int> evaluated;  ///< the representatives, in face order
};

Representatives pick_representatives(const std::vector<Vec3>& centres, const std::vector<Vec3>& normals, double cell,
                                     double plane_angle) {
  Representatives r;
  r.of_face.resize(centres.size());
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  for (std::size_t g = 0; g < centres.size(); ++g) {
    const Vec3 q = (centres[g] / cell).array().floor();
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a)
      key = key * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(static_cast<std::int64_t>(q[a]));
    std::vector<int>& reps = cells[key];
    const auto same = std::find_if(reps.begin(), reps.end(), [&](int k) {
      return normals[k].dot(normals[g]) > plane_angle && (centres[k] / cell).array().floor().matrix() == q;
    });
    if (same != reps.end()) {
      r.of_face[g] = *same;
    } else {
      r.of_face[g] = static_cast<int>(g);
      reps.push_back(static_cast<int>(g));
      r.evaluated.push_back(static_cast<int>(g));
    }
  }
  return r;
}

}  // namespace

SurfaceChange measure_surface_change(const SurfaceIndex& previous, const SurfaceIndex& next, double dt, double frames,
                                     double radius, double plane_angle) {
  if (!(radius > 0.0) || !(frames > 0.0)) throw InternalError("measure_surface_change: radius and frames must be > 0");
  const std::size_t nf_to = next.mesh().triangles.size();
  SurfaceChange out;
  out.rate.assign(nf_to, 0.0f);
  if (nf_to == 0) return out;
  const Landings landed = land_faces(previous, next, dt);
  // The next faces with the same smooth normal as the landings (vertex
  // normals blended at the centroid): face normals of a reconstructed
  // surface scatter where it bends, and the plane test would then keep
  // fewer faces than landings there.
  std::vector<Vec3> centres(nf_to), normals(nf_to);
  parallel_each(nf_to, [&](std::size_t g) {
    const SurfacePoint c = next.at(static_cast<int>(g), Vec3::Constant(1.0 / 3.0));
    centres[g] = c.position;
    normals[g] = next.normal_at(c);
  });
  const PointIndex carried_index(landed.position), next_index(centres);
  const Representatives reps = pick_representatives(centres, normals, radius / 4.0, plane_angle);

  // A ball that received (almost) nothing, or holds (almost) no surface,
  // reads as kMaxSurfaceChange rather than infinity: the floor is a
  // thousandth of the ball's area.
  const double floor = 1e-3 * M_PI * radius * radius;
  // A smooth weight that falls to 0 at the radius: a hard ball centred on
  // a face counts the faces of a mesh made on a grid (a solver's) shell by
  // shell, and the carried ones, shifted off the grid, otherwise: the ratio
  // then swings by several per cent with the radius alone.
  const double inv_r2 = 1.0 / (radius * radius);
  auto kernel = [inv_r2](const Vec3& a, const Vec3& b) {
    const double t = 1.0 - (a - b).squaredNorm() * inv_r2;
    return t > 0.0 ? t * t : 0.0;
  };
  const std::vector<double>& next_area = next.face_areas();
  const std::vector<double>& from_area = previous.face_areas();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, reps.evaluated.size()),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<int> hits;
                      for (std::size_t e = r.begin(); e != r.end(); ++e) {
                        const int g = reps.evaluated[e];
                        const Vec3& n = normals[g];
                        double here = 0.0, arrived = 0.0;
                        // The trees' order is the same on every run: a fixed summation order.
                        next_index.within(centres[g], radius, hits);
                        for (int h : hits) {
                          if (normals[h].dot(n) > plane_angle) here += next_area[h] * kernel(centres[h], centres[g]);
                        }
                        carried_index.within(centres[g], radius, hits);
                        for (int h : hits) {
                          if (landed.normal[h].dot(n) > plane_angle)
                            arrived += from_area[h] * kernel(landed.position[h], centres[g]);
                        }
                        const double change = std::log((here + floor) / (arrived + floor)) / frames;
                        out.rate[g] = static_cast<float>(std::clamp(change, -kMaxSurfaceChange, kMaxSurfaceChange));
                      }
                    });
  for (std::size_t g = 0; g < nf_to; ++g) out.rate[g] = out.rate[reps.of_face[g]];
  return out;
}

ChangeTally tally_change(const SurfaceIndex& surface, const SurfaceChange& change,
                         const std::vector<SurfacePoint>& centres, const std::vector<Vec3>& births,
                         const std::vector<Vec3>& removals) {
  ChangeTally tally;
  for (std::size_t f = 0; f < change.rate.size(); ++f) {
    const double area = surface.face_areas()[f], rate = change.rate[f];
    tally.area[change_class(rate)] += area;
    if (rate > 0.0)
      tally.made += area * -std::expm1(-rate);
    else
      tally.lost += area * std::expm1(-rate);
  }
  for (const SurfacePoint& c : centres) ++tally.patches[change_class(change.at(c))];
  auto count = [&](const std::vector<Vec3>& points, std::array<int, kChangeClasses>& per_class) {
    for (const Vec3& x : points) ++per_class[change_class(change.at(surface.closest_point(x)))];
  };
  count(births, tally.births);
  count(removals, tally.removals);
  return tally;
}

const char* change_class_name(int c) {
  static const char* names[kChangeClasses] = {"sink_fast", "sink", "kept", "source", "source_fast"};
  if (c < 0 || c >= kChangeClasses) throw InternalError("change_class_name: no class " + std::to_string(c));
  return names[c];
}

int change_class(double rate) {
  int c = 0;
  while (c < kChangeClasses - 1 && !(rate < kChangeClassEdges[c])) ++c;
  return c;
}

std::vector<std::pair<std::string, double>> ChangeTally::named() const {
  std::vector<std::pair<std::string, double>> out;
  auto add = [&](const char* what, auto const& values) {
    for (int c = 0; c < kChangeClasses; ++c)
      out.emplace_back(std::string("change_") + what + "_" + change_class_name(c), static_cast<double>(values[c]));
  };
  add("area", area);
  add("patches", patches);
  add("births", births);
  add("removals", removals);
  out.emplace_back("change_made_area", made);
  out.emplace_back("change_lost_area", lost);
  return out;
}

}  // namespace fluidtex
