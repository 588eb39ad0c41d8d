/// @file point_index.h
/// @brief Radius queries over a growing set of 3D points (disk centres,
/// vertices), on nanoflann's k-d trees. within() returns its results sorted
/// by index so that callers never depend on the trees' internal order; its
/// unordered form is for callers that order the results themselves.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "fluidtex/geometry/mesh.h"

namespace fluidtex {

class PointIndex {
 public:
  PointIndex();
  explicit PointIndex(const std::vector<Vec3>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  /// Adds a point; returns its index (0, 1, 2, … in insertion order).
  int add(const Vec3& p);
  std::size_t size() const;
  const Vec3& point(int i) const;

  /// Indices of the points closer than `radius` to `q`, ascending.
  /// Thread safe against other queries (not against add).
  std::vector<int> within(const Vec3& q, double radius) const;

  /// The same indices in no particular order (the trees' order, the same on
  /// every run), in `out` (cleared first): for callers that order them
  /// themselves and query often.
  void within(const Vec3& q, double radius, std::vector<int>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fluidtex
