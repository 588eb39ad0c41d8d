#include "fluidtex/geometry/distortion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fluidtex {

RestTriangle rest_shape(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const double l1 = e1.norm();
  if (!(l1 > 0.0)) return {Vec2(0, 0), Vec2(0, 0), Vec2(e2.norm(), 0)};
  const Vec3 x = e1 / l1;
  const Vec3 n = e1.cross(e2);
  // y: in the triangle's plane, perpendicular to x, towards p2.
  const Vec3 y = n.norm() > 0.0 ? Vec3(n.cross(x).normalized()) : Vec3::Zero();
  return {Vec2(0, 0), Vec2(l1, 0), Vec2(e2.dot(x), e2.dot(y))};
}

Stretch triangle_stretch(const RestTriangle& r, const Vec3& q1, const Vec3& q2, const Vec3& q3) {
  const double s1 = r[0].x(), t1 = r[0].y(), s2 = r[1].x(), t2 = r[1].y(), s3 = r[2].x(), t3 = r[2].y();
  const double area2 = (s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1);  // 2A, signed
  if (!(std::abs(area2) > 0.0)) return {std::numeric_limits<double>::infinity(), 0.0};
  const Vec3 Ss = (q1 * (t2 - t3) + q2 * (t3 - t1) + q3 * (t1 - t2)) / area2;
  const Vec3 St = (q1 * (s3 - s2) + q2 * (s1 - s3) + q3 * (s2 - s1)) / area2;
  const double a = Ss.dot(Ss), b = Ss.dot(St), c = St.dot(St);
  const double root = std::sqrt((a - c) * (a - c) + 4.0 * b * b);
  const double gmax = std::sqrt(std::max(0.0, 0.5 * ((a + c) + root)));
  const double gmin = std::sqrt(std::max(0.0, 0.5 * ((a + c) - root)));
  return {gmax, gmin};
}

double triangle_distortion(const RestTriangle& rest, const Vec3& q0, const Vec3& q1, const Vec3& q2) {
  const Stretch s = triangle_stretch(rest, q0, q1, q2);
  if (!(s.gamma_min > 1e-12)) return std::numeric_limits<double>::infinity();
  return std::max(s.gamma_max, 1.0 / s.gamma_min);
}

double triangle_quality(double distortion, double max_distortion) {
  if (!std::isfinite(distortion)) return 0.0;
  return std::max((max_distortion - distortion) / (max_distortion - 1.0), 0.0);
}

}  // namespace fluidtex
