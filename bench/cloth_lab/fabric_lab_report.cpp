// The fabric laboratory's tests on the simulated fabrics of data/fabrics.toml: prints the
// Markdown tables of docs/validation-fabric.md. References: the tensile curve integrated along
// a hanging strip, the heavy elastica of Peirce's cantilever and the bending length
// c = (B/W)^(1/3), the shear curve in a picture frame.
#include <cstdio>
#include <string>

#include "fabric_lab.hpp"
#include "scene/scene.hpp"

using namespace tactus;
using namespace tactus::physics;
using namespace tactus::physics::fabric_lab;

namespace {

/// A database fabric's material, read the way a scene reads it.
ClothMaterial database_fabric(const std::string& key, bool& illustrative) {
  const std::string scene = "[bodies.f]\nkind = \"cloth\"\nfabric = \"" + key + "\"\nsize = [0.1, 0.1]\nspacing = 0.02\n";
  const scene::Model m = scene::parse_scene(scene, std::string(TACTUS_SOURCE_DIR) + "/scenes/report.toml");
  illustrative = m.bodies[0].cloth->illustrative;
  return m.bodies[0].cloth->model->material();
}

void hang_table(const std::string& key, const ClothMaterial& m) {
  const double width = 0.20, length = 0.38;
  std::printf("\n#### Hang test, %s: 20 × 38 cm, warp hanging, load on the bottom edge\n\n", key.c_str());
  std::printf("| spacing | 0.4 N | 0.8 N | 1.2 N | 1.6 N | 2.0 N | 2.4 N | analytic at 2.4 N |\n|---|---|---|---|---|---|---|---|\n");
  for (double spacing : {0.02, 0.01, 0.005}) {
    Hang h = hanging_strip(m, width, length, spacing);
    std::printf("| %.0f mm |", spacing * 1e3);
    double analytic = 0.0;
    for (double load : {0.4, 0.8, 1.2, 1.6, 2.0, 2.4}) {
      bool converged = false;
      const double simulated = simulated_elongation(h, load, length, converged);
      analytic = analytic_elongation(m, load, width, length);
      std::printf(" %+.3f %%%s |", 100.0 * (simulated - analytic) / analytic, converged ? "" : " (not converged)");
    }
    std::printf(" %.2f mm |\n", analytic * 1e3);
  }
}

void cantilever_table(const std::string& key, const ClothMaterial& m) {
  const double c = std::cbrt(m.bend_warp.slope(0.0) / (m.areal_density * kGravity));
  const double deg = 180.0 / 3.14159265358979323846;
  std::printf("\n#### Peirce cantilever, %s (warp strip 2.5 cm wide): c = (B/W)^(1/3) = %.2f mm\n\n", key.c_str(), c * 1e3);
  std::printf("| bending | spacing | chord at l = 1.5c / 2c / 2.5c (elastica %.2f° / %.2f° / %.2f°) | bending length read at 41.5° | error |\n|---|---|---|---|---|\n",
              elastica_chord_angle(1.5) * deg, elastica_chord_angle(2.0) * deg, elastica_chord_angle(2.5) * deg);
  for (auto bending : {SheetBending::yarns, SheetBending::hinges})
    for (double cells : {4.0, 8.0, 16.0}) {
      const double spacing = c / cells;
      std::printf("| %s | c/%.0f |", bending == SheetBending::yarns ? "yarns" : "edge hinges (seed)", cells);
      for (double ratio : {1.5, 2.0, 2.5}) {
        bool converged = false;
        const double angle = simulated_chord_angle(m, ratio * c, spacing, converged, bending) * deg;
        std::printf(" %.2f°%s", angle, converged ? "" : " (not converged)");
      }
      bool converged = false;
      const double measured = peirce_bending_length(m, spacing, 1.2 * c, 3.0 * c, converged, bending);
      std::printf(" | %.2f mm%s | %+.2f %% |\n", measured * 1e3, converged ? "" : " (not converged)", 100.0 * (measured / c - 1.0));
    }
}

void picture_frame_table(const std::string& key, const ClothMaterial& m) {
  std::printf("\n#### Picture frame, %s: 10 × 10 cm at 10 mm\n\n| γ | frame force dE/dγ | side²·T_s(γ) | error |\n|---|---|---|---|\n",
              key.c_str());
  for (double gamma : {0.02, 0.05, 0.1, 0.15}) {
    bool converged = false;
    const double force = picture_frame_force(m, 0.1, gamma, converged);
    const double expected = 0.01 * m.shear.value(gamma);
    std::printf("| %.2f rad | %.4g N·m | %.4g N·m | %+.3f %%%s |\n", gamma, force, expected,
                100.0 * (force / expected - 1.0), converged ? "" : " (not converged)");
  }
}

}  // namespace

int main() {
  for (const char* key : {"denim", "cotton", "wool", "silk", "polyester"}) {
    bool illustrative = false;
    const ClothMaterial m = database_fabric(key, illustrative);
    std::printf("\n### %s%s\n", key, illustrative ? " (illustrative values)" : " (measured KES values)");
    hang_table(key, m);
    cantilever_table(key, m);
    picture_frame_table(key, m);
  }
  return 0;
}
