// PointIndex (geometry/point_index.h) against brute force, built at once,
// grown point by point, and built at once then grown (its two trees).
#include <gtest/gtest.h>

#include <algorithm>

#include "fluidtex/geometry/point_index.h"
#include "fluidtex/util/random.h"

namespace fluidtex {
namespace {

std::vector<int> brute_force(const std::vector<Vec3>& points, const Vec3& q, double r) {
  std::vector<int> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((points[i] - q).norm() < r) out.push_back(static_cast<int>(i));
  }
  return out;
}

Vec3 random_point(std::uint64_t i) {
  return Vec3(to_unit(hash_values({1, i})), to_unit(hash_values({2, i})), to_unit(hash_values({3, i})));
}

TEST(PointIndex, RadiusQueriesMatchBruteForce) {
  std::vector<Vec3> points;
  for (std::uint64_t i = 0; i < 2000; ++i) points.push_back(random_point(i));
  const PointIndex built(points);
  PointIndex grown;
  ASSERT_EQ(built.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(grown.add(points[i]), static_cast<int>(i));
    if (i % 97 == 0) {  // queries between additions see every point added so far
      const std::vector<Vec3> prefix(points.begin(), points.begin() + static_cast<std::ptrdiff_t>(i) + 1);
      const Vec3 q = random_point(10000 + i);
      EXPECT_EQ(grown.within(q, 0.2), brute_force(prefix, q, 0.2));
    }
  }
  for (std::uint64_t k = 0; k < 50; ++k) {
    const Vec3 q = random_point(20000 + k);
    for (double r : {0.0, 0.05, 0.3}) {
      EXPECT_EQ(built.within(q, r), brute_force(points, q, r)) << r;
      EXPECT_EQ(grown.within(q, r), brute_force(points, q, r)) << r;
    }
  }
  EXPECT_EQ(built.point(17), points[17]);
}

TEST(PointIndex, PointsAddedToABuiltIndexAreFoundWithTheOthers) {
  std::vector<Vec3> points;
  for (std::uint64_t i = 0; i < 1500; ++i) points.push_back(random_point(i));
  PointIndex index(std::vector<Vec3>(points.begin(), points.begin() + 1000));
  for (std::size_t i = 1000; i < points.size(); ++i) EXPECT_EQ(index.add(points[i]), static_cast<int>(i));
  ASSERT_EQ(index.size(), points.size());
  for (std::uint64_t k = 0; k < 50; ++k) {
    const Vec3 q = random_point(30000 + k);
    for (double r : {0.05, 0.3}) EXPECT_EQ(index.within(q, r), brute_force(points, q, r)) << r;
  }
  EXPECT_EQ(index.point(1200), points[1200]);
}

TEST(PointIndex, UnorderedQueriesFindTheSamePointsAndClearTheList) {
  std::vector<Vec3> points;
  for (std::uint64_t i = 0; i < 1200; ++i) points.push_back(random_point(i));
  PointIndex index(std::vector<Vec3>(points.begin(), points.begin() + 800));
  for (std::size_t i = 800; i < points.size(); ++i) index.add(points[i]);
  std::vector<int> found = {-1, -2};  // a caller's list from before: cleared
  for (std::uint64_t k = 0; k < 50; ++k) {
    const Vec3 q = random_point(40000 + k);
    for (double r : {0.0, 0.05, 0.3}) {
      index.within(q, r, found);
      std::sort(found.begin(), found.end());
      EXPECT_EQ(found, brute_force(points, q, r)) << r;
    }
  }
}

}  // namespace
}  // namespace fluidtex
