// A program outside the Tactus tree, built against an installed Tactus.
#include <cstdio>

#include "core/version.hpp"
#include "mesh/generators.hpp"

int main() {
  const auto s = tactus::mesh::sphere(1.0, 2);
  std::printf("tactus %s: sphere with %zu triangles\n", tactus::kVersion, s.triangles.size());
  return s.triangles.size() == 320 ? 0 : 1;
}
