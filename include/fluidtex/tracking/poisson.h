/// @file poisson.h
/// @brief Poisson-disk distribution on the free surface (Gagnon et al. 2019,
/// Sec. 4 and 5.4).
///
/// A candidate c with normal N_c is rejected by a disk at p with normal N only
/// when both criteria hold:
///  - plane test: N_c·N > pa ("in the same plane");
///  - k-criterion, Eq. 1: with (x, y, z) = c − p in the disk's tangent frame
///    (z along N), k = x²/r² + y²/r² + z²/cs² < 1.
/// `Criterion::Sphere` (plain |c − p| < r, Fig. 3a) and `Criterion::Plane`
/// (plane test and |c − p| < r, Fig. 3b) reproduce the paper's ablations.
/// The kill distance (Table 4) uses the same test with r = (1 − α)·d.
///
/// Sampling is dart throwing over a dense, seeded set of candidate points
/// spread over the triangles by area (so the result is maximal up to the
/// candidate spacing) visited in a seeded random order; deterministic for a
/// (seed, frame).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/tracking/options.h"

namespace fluidtex {

struct PoissonParams {
  double radius = 1.0;       ///< r = d
  double thickness = 0.25;   ///< cs
  double plane_angle = 0.5;  ///< pa
  Criterion criterion = Criterion::Ellipsoid;
};

/// Eq. 1: k of `c` relative to the disk at `p` with unit normal `n`.
double ellipsoid_k(const Vec3& p, const Vec3& n, const Vec3& c, double r, double cs);

/// The plane test: N_c·N > pa.
inline bool same_plane(const Vec3& n, const Vec3& nc, double pa) { return nc.dot(n) > pa; }

/// Does the disk (p, n) reject a candidate (c, nc) at radius `r`?
bool rejects(const Vec3& p, const Vec3& n, const Vec3& c, const Vec3& nc, double r, const PoissonParams& params);

/// A point on the surface with its unit normal.
struct SurfaceSample {
  SurfacePoint point;
  Vec3 normal = Vec3::UnitZ();
};

/// Candidate points, in visiting order: about `per_disk` random points per
/// disk area π r² spread by triangle area, every vertex on an open boundary
/// (they reach rims and corners), and every vertex and triangle centroid of
/// components too small to receive random points (thin splashes, droplets). The random streams are
/// keyed by face index, so an unchanged surface gives the same candidates.
std::vector<SurfaceSample> surface_candidates(const SurfaceIndex& surface, double radius, std::uint64_t seed,
                                              double per_disk = 32.0);

/// Dart throwing: keeps every candidate that no existing disk nor earlier kept
/// candidate rejects. Then any connected component with area above
/// `min_component_area` that still holds no disk (existing disks count by the
/// component of their face) gets its first candidate, so that small droplets
/// are never left bare. Returns the kept candidates in acceptance order.
///
/// `uncovered` (optional, one entry per candidate) marks candidates that no
/// existing patch actually covers with positive weight: such a candidate is
/// also kept when only existing disks reject it (new disks still do).
/// Departure from the paper, whose gap test looks at disk centres only: an
/// advected patch can lose vertices (mpt), shrink or be compressed, and then
/// no longer cover the disk its centre stands for; this keeps the surface
/// covered (Σw > 0 everywhere), which the blending needs.
///
/// `margin` (γ, `--birth-margin`): existing disks reject candidates at
/// (1 + γ)·r instead of r (kept candidates still reject each other at r).
/// Departure from the paper: births need a gap wider than the spacing a
/// fresh distribution has, a hysteresis band against the kill distance.
///
/// `reached` (optional): reached(k) holds when candidate k lies within the
/// reach of an existing patch's own disk, measured on that patch (the
/// tracker: within (1 + γ)·r of its centre in its uv). Such a candidate is
/// rejected like one an existing disk rejects, however far that disk's
/// centre has moved away in space. Asked only of candidates nothing else
/// rejects, and never of uncovered ones.
std::vector<SurfaceSample> fill_gaps(const std::vector<SurfaceSample>& existing,
                                     const std::vector<SurfaceSample>& candidates, const SurfaceIndex& surface,
                                     const PoissonParams& params, double min_component_area,
                                     const std::vector<char>* uncovered = nullptr, double margin = 0.0,
                                     const std::function<bool(std::size_t)>& reached = nullptr);

/// Kill-distance flags (Sec. 5.4): visiting `disks` in order (callers pass
/// them oldest first), a disk is flagged when an earlier, unflagged disk
/// rejects it at radius (1 − α)·d. So of two disks that come too close, the
/// younger fades out and the older one, already visible, stays.
///
/// With `redundant` (departure from the paper), a pair counts only when
/// redundant(older, younger) holds: the tracker passes "the older patch
/// covers the younger disk's centre". A disk seeded where an older patch
/// close by no longer covers the surface (it lost vertices, or the surface
/// grew there) is not redundant; retiring it would leave the surface bare
/// and the next update would seed it again, every frame.
std::vector<bool> flag_too_close(const std::vector<SurfaceSample>& disks, const PoissonParams& params,
                                 double kill_alpha,
                                 const std::function<bool(std::size_t, std::size_t)>& redundant = nullptr);

/// Density ρ (Sec. 6.3) of each of `disks`: how many other disks are in the
/// same plane within radius r (3D distance), whatever their state.
std::vector<int> disk_density(const std::vector<SurfaceSample>& disks, const PoissonParams& params);

}  // namespace fluidtex
