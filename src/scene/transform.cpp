// Affine transforms for placing meshes.
#include "rayscout/scene/transform.h"

#include <cmath>
#include <numbers>

namespace rayscout {

Transform Transform::translate(const Vec3& t) {
  Transform x;
  x.m[0][3] = t.x; x.m[1][3] = t.y; x.m[2][3] = t.z;
  return x;
}

Transform Transform::scale(const Vec3& s) {
  Transform x;
  x.m[0][0] = s.x; x.m[1][1] = s.y; x.m[2][2] = s.z;
  return x;
}

Transform Transform::rotate(const Vec3& axis, double deg) {
  // Rodrigues' rotation formula.
  double ax = axis.x, ay = axis.y, az = axis.z;
  const double len = std::sqrt(ax * ax + ay * ay + az * az);
  ax /= len; ay /= len; az /= len;
  const double a = deg * std::numbers::pi / 180.0;
  const double c = std::cos(a), s = std::sin(a), t = 1.0 - c;
  Transform x;
  x.m[0][0] = t * ax * ax + c;      x.m[0][1] = t * ax * ay - s * az; x.m[0][2] = t * ax * az + s * ay;
  x.m[1][0] = t * ax * ay + s * az; x.m[1][1] = t * ay * ay + c;      x.m[1][2] = t * ay * az - s * ax;
  x.m[2][0] = t * ax * az - s * ay; x.m[2][1] = t * ay * az + s * ax; x.m[2][2] = t * az * az + c;
  return x;
}

Transform Transform::operator*(const Transform& b) const {
  Transform r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double v = j == 3 ? m[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) v += m[i][k] * b.m[k][j];
      r.m[i][j] = v;
    }
  }
  return r;
}

Vec3 Transform::apply_point(const Vec3& p) const {
  double r[3];
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
  return {float(r[0]), float(r[1]), float(r[2])};
}

bool Transform::is_identity() const {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (m[i][j] != (i == j ? 1.0 : 0.0)) return false;
  return true;
}

double Transform::determinant() const {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

}  // namespace rayscout
