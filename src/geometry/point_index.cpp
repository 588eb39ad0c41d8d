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

std::vector<int> PointIndex::within(const Vec3& q, double radius) const {
  std::vector<int> out;
  const double query[3] = {q.x(), q.y(), q.z()};
  std::vector<std::pair<std::uint32_t, double>> found;
  if (impl_->fixed) {
    nanoflann::RadiusResultSet<double, std::uint32_t> result(radius * radius, found);
    impl_->fixed->findNeighbors(result, query, nanoflann::SearchParams());
    for (const auto& match : found) out.push_back(static_cast<int>(match.first));
  }
  if (impl_->added) {
    const int offset = static_cast<int>(impl_->fixed_cloud.points.size());
    nanoflann::RadiusResultSet<double, std::uint32_t> result(radius * radius, found);  // clears `found`
    impl_->added->findNeighbors(result, query, nanoflann::SearchParams());
    for (const auto& match : found) out.push_back(offset + static_cast<int>(match.first));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fluidtex
