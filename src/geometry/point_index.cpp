#include "fluidtex/geometry/point_index.h"

#include <algorithm>

// nanoflann's dynamic index trips a false -Wmaybe-uninitialized in GCC 12.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop

namespace fluidtex {

namespace {
struct Cloud {
  std::vector<Vec3> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return points[i][static_cast<int>(dim)]; }
  template <class BBOX>
  bool kdtree_get_bbox(BBOX&) const {
    return false;
  }
};
using Metric = nanoflann::L2_Simple_Adaptor<double, Cloud>;
using StaticTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, Cloud, 3, std::uint32_t>;
using DynamicTree = nanoflann::KDTreeSingleIndexDynamicAdaptor<Metric, Cloud, 3, std::uint32_t>;
}  // namespace

// The points given at construction go into a static tree (built once,
// faster to query); points added later into a dynamic one over a cloud of
// their own (nanoflann's dynamic tree indexes every point its cloud already
// holds when it is made).
struct PointIndex::Impl {
  Cloud fixed_cloud, added_cloud;  // points [0, fixed count), then the added ones
  // Constructed after the clouds (they keep a reference to them).
  std::unique_ptr<StaticTree> fixed;
  std::unique_ptr<DynamicTree> added;
};

PointIndex::PointIndex() : impl_(std::make_unique<Impl>()) {}

PointIndex::PointIndex(const std::vector<Vec3>& points) : PointIndex() {
  if (points.empty()) return;
  impl_->fixed_cloud.points = points;
  impl_->fixed = std::make_unique<StaticTree>(3, impl_->fixed_cloud,
                                              nanoflann::KDTreeSingleIndexAdaptorParams(10));  // built here
}

PointIndex::~PointIndex() = default;

int PointIndex::add(const Vec3& p) {
  if (!impl_->added)
    impl_->added = std::make_unique<DynamicTree>(3, impl_->added_cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->added_cloud.points.push_back(p);
  const auto i = static_cast<std::uint32_t>(impl_->added_cloud.points.size() - 1);
  impl_->added->addPoints(i, i);
  return static_cast<int>(impl_->fixed_cloud.points.size() + i);
}

std::size_t PointIndex::size() const { return impl_->fixed_cloud.points.size() + impl_->added_cloud.points.size(); }
const Vec3& PointIndex::point(int i) const {
  const std::size_t n = impl_->fixed_cloud.points.size();
  return static_cast<std::size_t>(i) < n ? impl_->fixed_cloud.points[i] : impl_->added_cloud.points[i - n];
}

namespace {

/// A nanoflann result set that appends the indices (plus an offset) of the
/// points within the radius to a vector: no pairs, no sorting.
struct Collect {
  using DistanceType = double;
  using IndexType = std::uint32_t;
  double radius2;
  int offset;
  std::vector<int>& out;
  bool full() const { return true; }
  double worstDist() const { return radius2; }
  bool addPoint(double dist2, std::uint32_t index) {
    if (dist2 < radius2) out.push_back(offset + static_cast<int>(index));
    return true;
  }
};

}  // namespace

void PointIndex::within(const Vec3& q, double radius, std::vector<int>& out) const {
  out.clear();
  const double query[3] = {q.x(), q.y(), q.z()};
  if (impl_->fixed) {
    Collect result{radius * radius, 0, out};
    impl_->fixed->findNeighbors(result, query, nanoflann::SearchParams());
  }
  if (impl_->added) {
    Collect result{radius * radius, static_cast<int>(impl_->fixed_cloud.points.size()), out};
    impl_->added->findNeighbors(result, query, nanoflann::SearchParams());
  }
}

std::vector<int> PointIndex::within(const Vec3& q, double radius) const {
  std::vector<int> out;
  within(q, radius, out);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fluidtex
