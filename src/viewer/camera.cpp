#include "viewer/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tactus::viewer {
namespace {

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

}  // namespace

OrbitCamera OrbitCamera::framing(const Aabb& box, double azimuth_deg, double elevation_deg) {
  OrbitCamera c;
  c.target = 0.5 * (box.min + box.max);
  const double radius = std::max(0.5 * (box.max - box.min).norm(), 1e-3);
  // Fills the view with the scene: its bounding sphere just fits the shorter side.
  c.distance = radius / std::tan(radians(c.fov_y) * 0.5) * 0.8;
  c.azimuth = azimuth_deg;
  c.elevation = std::clamp(elevation_deg, -89.0, 89.0);
  return c;
}

Vec3 OrbitCamera::eye() const {
  const double az = radians(azimuth), el = radians(elevation);
  return target + distance * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

Vec3 OrbitCamera::right() const {
  const double az = radians(azimuth);
  return Vec3(-std::sin(az), std::cos(az), 0.0);
}

Vec3 OrbitCamera::up() const {
  const Vec3 forward = (target - eye()).normalized();
  return right().cross(forward).normalized();
}

Mat4f OrbitCamera::view() const {
  const Vec3 e = eye();
  const Vec3 f = (target - e).normalized();
  const Vec3 r = right();
  const Vec3 u = r.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -r.dot(e);
  m(1, 3) = -u.dot(e);
  m(2, 3) = f.dot(e);
  return m.cast<float>();
}

Mat4f OrbitCamera::projection(double aspect) const {
  // Near and far follow the distance so that small and large scenes keep their depth precision.
  const double n = distance * 0.02, f = distance * 20.0;
  const double t = 1.0 / std::tan(radians(fov_y) * 0.5);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / std::max(aspect, 1e-6);
  p(1, 1) = t;
  p(2, 2) = -(f + n) / (f - n);
  p(2, 3) = -2.0 * f * n / (f - n);
  p(3, 2) = -1.0;
  return p.cast<float>();
}

void OrbitCamera::orbit(double d_azimuth, double d_elevation) {
  azimuth = std::fmod(azimuth + d_azimuth, 360.0);
  elevation = std::clamp(elevation + d_elevation, -89.0, 89.0);
}

void OrbitCamera::pan(double dx_fraction, double dy_fraction) {
  const double height = 2.0 * distance * std::tan(radians(fov_y) * 0.5);
  target += height * (dx_fraction * right() + dy_fraction * up());
}

void OrbitCamera::zoom(double factor) {
  if (factor > 0.0 && std::isfinite(factor)) distance = std::clamp(distance * factor, 1e-4, 1e3);
}

bool OrbitCamera::project(const Vec3& p, int width, int height, double& x, double& y) const {
  const Eigen::Vector4f clip = projection(static_cast<double>(width) / height) * view() *
                               Eigen::Vector4f(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                               static_cast<float>(p.z()), 1.0f);
  if (clip.w() <= 0.0f) return false;
  x = (clip.x() / clip.w() * 0.5 + 0.5) * width;
  y = (0.5 - clip.y() / clip.w() * 0.5) * height;
  return true;
}

}  // namespace tactus::viewer
