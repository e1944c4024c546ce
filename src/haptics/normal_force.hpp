#pragma once
// Normal-force laws of a probe or fingerpad pressed a depth d into the local contact plane
// (Hertz contact with curvature is contact/hertz.hpp).
#include <cmath>

namespace tactus::haptics {

enum class NormalLaw {
  linear,     ///< F = k·d (virtual coupling spring of a proxy)
  fingerpad,  ///< F = (b/m)(e^{m·d} − 1) (Pawluk & Howe, seed 002 eq. 1)
};

struct NormalForceLaw {
  NormalLaw law = NormalLaw::linear;
  double stiffness = 500.0;     ///< linear: k [N/m]
  double b = 190.0;             ///< fingerpad [N/m]
  double m = 2100.0;            ///< fingerpad [1/m]

  /// Force [N] at depth d [m]; zero for d ≤ 0.
  [[nodiscard]] double force(double d) const {
    if (!(d > 0.0)) return 0.0;
    switch (law) {
      case NormalLaw::linear: return stiffness * d;
      case NormalLaw::fingerpad: return b / m * std::expm1(m * d);
    }
    return 0.0;
  }
};

}  // namespace tactus::haptics
