// Small double-precision vector and matrix helpers for camera math (host side only).
// Mat4 is row-major: m[4 * row + column]; points are column vectors, p' = M p.
#pragma once

#include <array>
#include <cmath>

namespace smokesvd {

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<double, 9>;   // row-major
using Mat4 = std::array<double, 16>;  // row-major

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) { return (1.0 / length(a)) * a; }

inline Mat4 identity4() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k)
      for (int col = 0; col < 4; ++col) c[4 * r + col] += a[4 * r + k] * b[4 * k + col];
  return c;
}

// M (p, 1) for an affine M (the last row is ignored).
inline Vec3 transformPoint(const Mat4& m, const Vec3& p) {
  Vec3 q{};
  for (int r = 0; r < 3; ++r) q[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
  return q;
}

// M (d, 0): the linear part applied to a direction.
inline Vec3 transformDirection(const Mat4& m, const Vec3& d) {
  Vec3 q{};
  for (int r = 0; r < 3; ++r) q[r] = m[4 * r] * d[0] + m[4 * r + 1] * d[1] + m[4 * r + 2] * d[2];
  return q;
}

// Inverse of an affine 4x4 (last row 0 0 0 1); returns false if the linear part is singular.
bool invertAffine(const Mat4& m, Mat4& inverse);

}  // namespace smokesvd
