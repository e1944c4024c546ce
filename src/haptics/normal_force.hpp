#pragma once
// Normal-force laws of a fingertip or probe pressed a depth d into tissue: the force a
// contact renders from the penetration of the tool into the local contact plane.
#include <cmath>

namespace tactus::haptics {

enum class NormalLaw {
  linear,     ///< F = k·d (virtual coupling spring of a proxy)
  hertz,      ///< F = 4/3·E*·√R·d^{3/2} (sphere on an elastic half-space)
  fingerpad,  ///< F = (b/m)(e^{m·d} − 1) (Pawluk & Howe, seed 002 eq. 1)
};

struct NormalForceLaw {
  NormalLaw law = NormalLaw::linear;
  double stiffness = 500.0;     ///< linear: k [N/m]
  double hertz_factor = 0.0;    ///< hertz: 4/3·E*·√R [N/m^{3/2}]
  double b = 190.0;             ///< fingerpad [N/m]
  double m = 2100.0;            ///< fingerpad [1/m]

  /// Force [N] at depth d [m]; zero for d ≤ 0.
  [[nodiscard]] double force(double d) const {
    if (!(d > 0.0)) return 0.0;
    switch (law) {
      case NormalLaw::linear: return stiffness * d;
      case NormalLaw::hertz: return hertz_factor * d * std::sqrt(d);
      case NormalLaw::fingerpad: return b / m * std::expm1(m * d);
    }
    return 0.0;
  }
};

/// The contact modulus E* of two elastic bodies: 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2.
[[nodiscard]] inline double contact_modulus(double e1, double nu1, double e2, double nu2) {
  return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
}

/// 4/3·E*·√R for a sphere of radius R.
[[nodiscard]] inline double hertz_factor(double contact_modulus_pa, double radius) {
  return 4.0 / 3.0 * contact_modulus_pa * std::sqrt(radius);
}

}  // namespace tactus::haptics
