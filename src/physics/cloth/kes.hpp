#pragma once
// From a fabric's Kawabata (KES-FB) measurements, in the units they are published in, to
// the curves of ClothMaterial (docs/fabrics.md derives each conversion).
#include "physics/cloth/cloth_model.hpp"

namespace tactus::physics {

/// One direction's KES values.
struct KesDirection {
  double emt = 0.0;  ///< EMT: strain at the maximum tensile load [%]
  double lt = 0.0;   ///< LT: linearity of the tensile curve (0, 1]
  double wt = 0.0;   ///< WT: tensile energy [gf·cm/cm²]
  double b = 0.0;    ///< B: bending rigidity [gf·cm²/cm]
  double g = 0.0;    ///< G: shear stiffness [gf/(cm·degree)]
  double hg = 0.0;   ///< 2HG: the shear loop's width at 0.5° [gf/cm]; 0: not measured
  double hg5 = 0.0;  ///< 2HG5: the shear loop's width at 5° [gf/cm]; 0: not measured
};

struct KesFabric {
  KesDirection warp, weft;
  double w = 0.0;                    ///< W: areal weight [mg/cm²]
  double tensile_max_load = 500.0;   ///< F_m of the tensile test [gf/cm]
};

inline constexpr double kGramForce = 9.80665e-3;  ///< [N]

/// Tension per unit width [N/m] against strain: F_m (ε/ε_m)^n with ε_m = EMT/100 and
/// n = 2/LT − 1, the one-parameter family through (ε_m, F_m) whose area is WT = LT·½F_m ε_m;
/// sampled at 24 points up to ε_m, along its tangent beyond. Under compression the fabric
/// buckles: it resists with 1 % of the secant modulus F_m/ε_m. Throws InputError naming
/// `what` where EMT, LT or F_m is out of range.
MeasuredCurve kes_tensile_curve(const KesDirection& d, double tensile_max_load, const std::string& what);

/// The ClothMaterial of a KES fabric: tensile curves as above, shear T = G·γ (the mean of
/// warp and weft G, converted to N/m per radian), shear friction H = 2HG/2 (the mean of warp
/// and weft, N/m; 0 where not measured), bending M = B·K per direction (N·m), areal density
/// W·0.01 kg/m². Damping time constants are the caller's.
ClothMaterial kes_material(const KesFabric& fabric, const std::string& what);

/// Relative mismatch of WT against LT·½F_m·ε_m (the definition of LT): a check on published data.
double kes_tensile_energy_mismatch(const KesDirection& d, double tensile_max_load);

}  // namespace tactus::physics
