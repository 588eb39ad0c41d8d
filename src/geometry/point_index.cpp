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
using Tree =
    nanoflann::KDTreeSingleIndexDynamicAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, std::uint32_t>;
}  // namespace

struct PointIndex::Impl {
  Cloud cloud;
  // Constructed after `cloud` (it keeps a reference to it).
  std::unique_ptr<Tree> tree;
};

PointIndex::PointIndex() : impl_(std::make_unique<Impl>()) {
  impl_->tree = std::make_unique<Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
}

PointIndex::PointIndex(const std::vector<Vec3>& points) : PointIndex() {
  if (points.empty()) return;
  impl_->cloud.points = points;
  impl_->tree->addPoints(0, static_cast<std::uint32_t>(points.size() - 1));
}

PointIndex::~PointIndex() = default;

int PointIndex::add(const Vec3& p) {
  impl_->cloud.points.push_back(p);
  const auto i = static_cast<std::uint32_t>(impl_->cloud.points.size() - 1);
  impl_->tree->addPoints(i, i);
  return static_cast<int>(i);
}

std::size_t PointIndex::size() const { return impl_->cloud.points.size(); }
const Vec3& PointIndex::point(int i) const { return impl_->cloud.points[i]; }

std::vector<int> PointIndex::within(const Vec3& q, double radius) const {
  std::vector<std::pair<std::uint32_t, double>> found;
  if (impl_->cloud.points.empty()) return {};
  nanoflann::RadiusResultSet<double, std::uint32_t> result(radius * radius, found);
  const double query[3] = {q.x(), q.y(), q.z()};
  impl_->tree->findNeighbors(result, query, nanoflann::SearchParams());
  std::vector<int> out;
  out.reserve(found.size());
  for (const auto& match : found) out.push_back(static_cast<int>(match.first));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fluidtex
