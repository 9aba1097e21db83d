#pragma once

#include <array>
#include <cmath>

// The simulator's own small geometry (it shares none with slam_core).
namespace cleanslam::sim_hal::sim {

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(double s, Vec3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) {
  return std::sqrt(dot(a, a));
}

// 3x3 rotation, row-major: m[r][c].
struct Mat3 {
  std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

inline Vec3 operator*(const Mat3& a, Vec3 v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
inline Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    }
  }
  return r;
}
inline Mat3 transpose(const Mat3& a) {
  Mat3 r;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      r.m[i][j] = a.m[j][i];
    }
  }
  return r;
}
inline Mat3 rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{{{1, 0, 0}, {0, c, -s}, {0, s, c}}}};
}
inline Mat3 rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}}};
}
inline Mat3 rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}}};
}

// Quaternion (w, x, y, z) of a rotation matrix (Shepperd's method), w >= 0.
std::array<double, 4> quaternion_wxyz(const Mat3& r);

// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

struct Pose3 {
  Mat3 rotation;  // body to world
  Vec3 position;
  [[nodiscard]] Vec3 apply(Vec3 p) const { return rotation * p + position; }
  [[nodiscard]] Vec3 apply_inverse(Vec3 p) const { return transpose(rotation) * (p - position); }
};
inline Pose3 compose(const Pose3& a, const Pose3& b) {
  return Pose3{a.rotation * b.rotation, a.apply(b.position)};
}

}  // namespace cleanslam::sim_hal::sim
