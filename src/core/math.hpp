#pragma once
// Math vocabulary: Eigen types under short names, used across every layer.
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tactus {

using Scalar = double;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Quat = Eigen::Quaterniond;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Axis-aligned box; empty until the first point is added.
struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  void add(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  [[nodiscard]] bool empty() const { return (min.array() > max.array()).any(); }
  [[nodiscard]] Vec3 size() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
  [[nodiscard]] Vec3 center() const { return 0.5 * (min + max); }
  [[nodiscard]] bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

}  // namespace tactus
