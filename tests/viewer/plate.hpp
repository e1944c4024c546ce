#pragma once
// A flat test surface for the viewer's tests: a square plate in z = 0.
#include <string>

#include "viewer/frame.hpp"

namespace tactus::viewer::test {

/// A square plate of side 2·half in z = 0, split into n × n cells (two triangles each).
inline SurfaceView plate(const std::string& name, double half, int n, const Colour& colour = SurfaceView{}.colour) {
  SurfaceView s;
  s.name = name;
  s.colour = colour;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.positions.emplace_back(-half + 2.0 * half * i / n, -half + 2.0 * half * j / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      s.triangles.push_back({a, a + 1, a + n + 2});
      s.triangles.push_back({a, a + n + 2, a + n + 1});
    }
  return s;
}

}  // namespace tactus::viewer::test
