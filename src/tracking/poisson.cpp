#include "fluidtex/tracking/poisson.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

double ellipsoid_k(const Vec3& p, const Vec3& n, const Vec3& c, double r, double cs) {
  const Vec3 d = c - p;
  const double z = d.dot(n);
  const double planar2 = std::max(0.0, d.squaredNorm() - z * z);  // x² + y²
  return planar2 / (r * r) + z * z / (cs * cs);
}

bool rejects(const Vec3& p, const Vec3& n, const Vec3& c, const Vec3& nc, double r, const PoissonParams& params) {
  switch (params.criterion) {
    case Criterion::Sphere: return (c - p).squaredNorm() < r * r;
    case Criterion::Plane: return same_plane(n, nc, params.plane_angle) && (c - p).squaredNorm() < r * r;
    case Criterion::Ellipsoid:
      return same_plane(n, nc, params.plane_angle) && ellipsoid_k(p, n, c, r, params.thickness) < 1.0;
  }
  return false;
}

namespace {

/// Radius that bounds the rejection region of any criterion.
double search_radius(double r, const PoissonParams& params) {
  return params.criterion == Criterion::Ellipsoid ? std::max(r, params.thickness) : r;
}

SurfaceSample sample_at(const SurfaceIndex& surface, int face, const Vec3& bary) {
  SurfaceSample s;
  s.point = surface.at(face, bary);
  s.normal = surface.normal_at(s.point);
  return s;
}

}  // namespace

std::vector<SurfaceSample> surface_candidates(const SurfaceIndex& surface, double radius, std::uint64_t seed,
                                              double per_disk) {
  const FrameMesh& mesh = surface.mesh();
  const std::size_t nf = mesh.triangles.size();
  const double density = per_disk / (M_PI * radius * radius);  // candidates per unit area
  struct Keyed {
    std::uint64_t key;
    SurfaceSample sample;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(static_cast<std::size_t>(density * surface.area()) + mesh.positions.size() + 16);
  auto key = [&](std::uint64_t a, std::uint64_t b) {
    return hash_values({seed, static_cast<std::uint64_t>(Stream::CandidateOrder), a, b});
  };
  // Components expecting fewer than a handful of random points also get
  // every face centroid as a candidate.
  std::vector<char> sparse(surface.num_components(), 0);
  for (int c = 0; c < surface.num_components(); ++c) sparse[c] = surface.component_area()[c] * density < 8.0;

  // The seeds depend on the face index, not on the frame, so that an
  // unchanged surface yields the same candidates (and no new disks).
  std::vector<char> vertex_done(mesh.positions.size(), 0);
  for (std::size_t f = 0; f < nf; ++f) {
    const double expected = surface.face_areas()[f] * density;
    const double whole = std::floor(expected);
    const int count =
        static_cast<int>(whole) + (uniform(seed, Stream::Candidates, f, ~0ULL) < expected - whole ? 1 : 0);
    for (int k = 0; k < count; ++k) {
      // Uniform point in the triangle (square-root parameterisation).
      const double u = uniform(seed, Stream::Candidates, f, 2 * k);
      const double v = uniform(seed, Stream::Candidates, f, 2 * k + 1);
      const double su = std::sqrt(u);
      keyed.push_back({key(f, k), sample_at(surface, static_cast<int>(f), Vec3(1.0 - su, su * (1.0 - v), su * v))});
    }
    if (sparse[surface.face_component()[f]]) {
      keyed.push_back({key(f, ~0ULL), sample_at(surface, static_cast<int>(f), Vec3::Constant(1.0 / 3.0))});
    }
    // Rim vertices too: they reach the corners and rims random points miss.
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles[f][c];
      if (vertex_done[v] || !(surface.vertex_on_boundary()[v] || sparse[surface.face_component()[f]])) continue;
      vertex_done[v] = 1;
      Vec3 bary = Vec3::Zero();
      bary[c] = 1.0;
      keyed.push_back({key(~static_cast<std::uint64_t>(v), 0), sample_at(surface, static_cast<int>(f), bary)});
    }
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    if (a.key != b.key) return a.key < b.key;
    return a.sample.point.face < b.sample.point.face;
  });
  std::vector<SurfaceSample> out;
  out.reserve(keyed.size());
  for (Keyed& k : keyed) out.push_back(std::move(k.sample));
  return out;
}

std::vector<SurfaceSample> fill_gaps(const std::vector<SurfaceSample>& existing,
                                     const std::vector<SurfaceSample>& candidates, const SurfaceIndex& surface,
                                     const PoissonParams& params, double min_component_area,
                                     const std::vector<char>* uncovered, double margin,
                                     const std::function<bool(std::size_t)>& reached) {
  const PointIndex old_index([&] {
    std::vector<Vec3> centres;
    centres.reserve(existing.size());
    for (const SurfaceSample& d : existing) centres.push_back(d.point.position);
    return centres;
  }());
  PointIndex new_index;
  std::vector<SurfaceSample> kept;
  auto accept = [&](const SurfaceSample& c) {
    kept.push_back(c);
    new_index.add(c.point.position);
  };
  auto rejected_by = [&](const PointIndex& index, const std::vector<SurfaceSample>& disks, const SurfaceSample& c,
                         double r) {
    for (int i : index.within(c.point.position, search_radius(r, params))) {
      if (rejects(disks[i].point.position, disks[i].normal, c.point.position, c.normal, r, params)) return true;
    }
    return false;
  };
  const double birth_radius = (1.0 + margin) * params.radius;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const SurfaceSample& c = candidates[k];
    if (rejected_by(new_index, kept, c, params.radius)) continue;
    if (!(uncovered && (*uncovered)[k]) &&
        (rejected_by(old_index, existing, c, birth_radius) || (reached && reached(k)))) {
      continue;
    }
    accept(c);
  }
  // Safety net for tiny components the criterion could not reach.
  std::vector<char> has_disk(surface.num_components(), 0);
  for (const std::vector<SurfaceSample>* list : {&existing, const_cast<const std::vector<SurfaceSample>*>(&kept)}) {
    for (const SurfaceSample& d : *list) {
      if (d.point.valid()) has_disk[surface.face_component()[d.point.face]] = 1;
    }
  }
  for (const SurfaceSample& c : candidates) {
    const int comp = surface.face_component()[c.point.face];
    if (!has_disk[comp] && surface.component_area()[comp] > min_component_area) {
      accept(c);
      has_disk[comp] = 1;
    }
  }
  return kept;
}

std::vector<bool> flag_too_close(const std::vector<SurfaceSample>& disks, const PoissonParams& params,
                                 double kill_alpha, const std::function<bool(std::size_t, std::size_t)>& redundant) {
  const double kill = (1.0 - kill_alpha) * params.radius;
  const double reach = search_radius(kill, params);
  std::vector<bool> flagged(disks.size(), false);
  PointIndex kept_index;
  std::vector<int> kept;  // indices into disks, parallel to kept_index
  for (std::size_t i = 0; i < disks.size(); ++i) {
    const SurfaceSample& c = disks[i];
    for (int j : kept_index.within(c.point.position, reach)) {
      const SurfaceSample& d = disks[kept[j]];
      if (rejects(d.point.position, d.normal, c.point.position, c.normal, kill, params) &&
          (!redundant || redundant(static_cast<std::size_t>(kept[j]), i))) {
        flagged[i] = true;
        break;
      }
    }
    if (!flagged[i]) {
      kept_index.add(c.point.position);
      kept.push_back(static_cast<int>(i));
    }
  }
  return flagged;
}

std::vector<int> disk_density(const std::vector<SurfaceSample>& disks, const PoissonParams& params) {
  std::vector<Vec3> centres;
  centres.reserve(disks.size());
  for (const SurfaceSample& d : disks) centres.push_back(d.point.position);
  const PointIndex index(centres);
  std::vector<int> rho(disks.size(), 0);
  for (std::size_t i = 0; i < disks.size(); ++i) {
    for (int j : index.within(centres[i], params.radius)) {
      if (static_cast<std::size_t>(j) != i && same_plane(disks[i].normal, disks[j].normal, params.plane_angle)) {
        ++rho[i];
      }
    }
  }
  return rho;
}

}  // namespace fluidtex
