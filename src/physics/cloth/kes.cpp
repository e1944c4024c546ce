#include "physics/cloth/kes.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tactus::physics {
namespace {
constexpr double kGfPerCm = kGramForce / 1e-2;  // 1 gf/cm in N/m
}

MeasuredCurve kes_tensile_curve(const KesDirection& d, double tensile_max_load, const std::string& what) {
  if (!(d.emt > 0.0 && d.emt < 100.0)) throw InputError(what + ": EMT must be in (0, 100) %");
  if (!(d.lt > 0.0 && d.lt <= 1.0)) throw InputError(what + ": LT must be in (0, 1]");
  if (!(tensile_max_load > 0.0 && std::isfinite(tensile_max_load)))
    throw InputError(what + ": the maximum tensile load must be positive");
  const double strain = d.emt / 100.0, force = tensile_max_load * kGfPerCm, n = 2.0 / d.lt - 1.0;
  constexpr int kPoints = 24;
  std::vector<double> x, y;
  for (int k = 0; k <= kPoints; ++k) {
    const double r = static_cast<double>(k) / kPoints;
    x.push_back(r * strain);
    y.push_back(force * std::pow(r, n));
  }
  return MeasuredCurve(std::move(x), std::move(y), MeasuredCurve::BelowZero::linear, 0.01 * force / strain, what);
}

ClothMaterial kes_material(const KesFabric& fabric, const std::string& what) {
  for (double v : {fabric.warp.b, fabric.weft.b, fabric.warp.g, fabric.weft.g})
    if (!(v > 0.0 && std::isfinite(v))) throw InputError(what + ": B and G must be positive");
  for (double v : {fabric.warp.hg, fabric.weft.hg, fabric.warp.hg5, fabric.weft.hg5})
    if (!(v >= 0.0 && std::isfinite(v))) throw InputError(what + ": 2HG and 2HG5 must be finite and >= 0");
  if (!(fabric.w > 0.0 && std::isfinite(fabric.w))) throw InputError(what + ": the weight W must be positive");
  ClothMaterial m;
  m.warp = kes_tensile_curve(fabric.warp, fabric.tensile_max_load, what + " (warp)");
  m.weft = kes_tensile_curve(fabric.weft, fabric.tensile_max_load, what + " (weft)");
  const double g = 0.5 * (fabric.warp.g + fabric.weft.g) * kGfPerCm * 180.0 / std::numbers::pi;
  m.shear = MeasuredCurve::line(g, what + " (shear)");
  m.shear_friction = 0.25 * (fabric.warp.hg + fabric.weft.hg) * kGfPerCm;
  // 2HG5 only where both directions give it (else the one width, 2HG).
  if (fabric.warp.hg5 > 0.0 && fabric.weft.hg5 > 0.0) m.shear_friction_5 = 0.25 * (fabric.warp.hg5 + fabric.weft.hg5) * kGfPerCm;
  constexpr double kGfCm2PerCm = kGramForce * 1e-4 / 1e-2;  // 1 gf·cm²/cm in N·m
  m.bend_warp = MeasuredCurve::line(fabric.warp.b * kGfCm2PerCm, what + " (warp bending)");
  m.bend_weft = MeasuredCurve::line(fabric.weft.b * kGfCm2PerCm, what + " (weft bending)");
  m.areal_density = fabric.w * 0.01;
  return m;
}

double kes_tensile_energy_mismatch(const KesDirection& d, double tensile_max_load) {
  const double expected = d.lt * 0.5 * tensile_max_load * d.emt;  // gf/cm × % → gf·cm/cm² × 100
  return std::abs(d.wt * 100.0 - expected) / expected;
}

}  // namespace tactus::physics
