#pragma once
// An orbit camera around a target point, z up (gravity points down z in every scene).
#include <Eigen/Core>

#include "core/math.hpp"

namespace tactus::viewer {

using Mat4f = Eigen::Matrix4f;

struct OrbitCamera {
  Vec3 target = Vec3::Zero();
  double azimuth = 30.0;     ///< [deg] about z, from +x
  double elevation = 35.0;   ///< [deg] above the xy plane, in (−89, 89)
  double distance = 0.2;     ///< [m] from the target
  double fov_y = 40.0;       ///< [deg] vertical field of view

  /// A view of the whole box from the given direction (az, el in degrees).
  static OrbitCamera framing(const Aabb& box, double azimuth_deg = 30.0, double elevation_deg = 35.0);

  [[nodiscard]] Vec3 eye() const;
  [[nodiscard]] Mat4f view() const;
  [[nodiscard]] Mat4f projection(double aspect) const;

  /// Rotates by mouse motion [deg]; elevation stays within (−89, 89).
  void orbit(double d_azimuth, double d_elevation);
  /// Moves the target in the view plane by a fraction of the view's height.
  void pan(double dx_fraction, double dy_fraction);
  /// Multiplies the distance (> 0) by `factor`.
  void zoom(double factor);
  /// Right and up unit vectors of the view plane, scene coordinates.
  [[nodiscard]] Vec3 right() const;
  [[nodiscard]] Vec3 up() const;

  /// Pixel (x right, y down) of a scene point in a width × height image; false when the
  /// point is behind the camera.
  bool project(const Vec3& p, int width, int height, double& x, double& y) const;
};

}  // namespace tactus::viewer
