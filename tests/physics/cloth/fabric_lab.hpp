#pragma once
// The fabric laboratory's tests on the simulated fabric and their references (the tensile
// curve integrated along a hanging strip, the heavy elastica of Peirce's cantilever): shared
// by the tests (tests/physics/cloth) and the report that fills docs/validation-fabric.md
// (bench/cloth_lab).
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "physics/body.hpp"
#include "physics/cloth/kes.hpp"
#include "physics/cloth/sheet.hpp"

namespace tactus::physics::fabric_lab {

constexpr double kGravity = 9.81;

/// A plain-weave cotton-like fabric (KES-style values of the order published for shirting).
inline KesFabric test_fabric() {
  KesFabric f;
  f.warp = {6.0, 0.70, 0.0, 0.10, 1.0};
  f.weft = {9.0, 0.65, 0.0, 0.07, 1.0};
  f.w = 13.0;
  return f;
}

/// The strain at tension T [N/m] on a monotone curve (bisection).
inline double inverse(const MeasuredCurve& c, double tension) {
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (c.value(mid) < tension ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Hang {
  SheetGrid grid;
  Body body;
  BodyState state;
};

/// A width × length strip, warp hanging down (−z), its top row clamped.
inline Hang hanging_strip(const ClothMaterial& m, double width, double length, double spacing) {
  Hang h{rectangular_sheet(length, width, spacing, Vec3::Zero(), -Vec3::UnitZ(), Vec3::UnitX()), {}, {}};
  h.body.model = std::make_shared<ClothModel>(h.grid.cloth, m);
  h.body.gravity = Vec3(0.0, 0.0, -kGravity);
  // CG: the flat, slack sheet's tangent is singular (it may swing about its top edge) until
  // the load tensions it; the loads have no part along that swing, so CG converges.
  h.body.settings.cg_tolerance = 1e-12;
  h.body.settings.cg_max_iterations = 5000;
  std::vector<std::int32_t> top;
  for (int j = 0; j < h.grid.nodes_v; ++j) top.push_back(h.grid.at(0, j));
  h.body.fix_nodes(top);
  h.state = make_state(h.body);
  return h;
}

/// Elongation of the hanging strip's bottom edge under a load P [N] on it, solved statically.
inline double simulated_elongation(Hang& h, double load, double length, bool& converged) {
  VecX f = VecX::Zero(h.state.x.size());
  const int last = h.grid.nodes_u - 1, columns = h.grid.nodes_v - 1;
  for (int j = 0; j <= columns; ++j)  // the consistent loads of a uniform line load
    f[3 * h.grid.at(last, j) + 2] = -load / columns * ((j == 0 || j == columns) ? 0.5 : 1.0);
  const auto result = solve_static(h.body, h.state, f, StaticSettings{200, 1e-10, 1e-12});
  converged = result.converged;
  return -h.state.x[3 * h.grid.at(last, h.grid.nodes_v / 2) + 2] - length;
}

/// ∫0^L ε(T(y)) dy with T(y) = P/w + ρ_A g y, the tension at height y above the bottom
/// (Simpson's rule on a fine grid).
inline double analytic_elongation(const ClothMaterial& m, double load, double width, double length) {
  const int n = 4000;
  auto strain = [&](double y) { return inverse(m.warp, load / width + m.areal_density * kGravity * y); };
  double sum = strain(0.0) + strain(length);
  for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * strain(length * k / n);
  return sum * length / (3.0 * n);
}

/// The heavy elastica of Peirce's cantilever: a strip of bending length c (c³ = B/w) and
/// overhang l, clamped level at s = 0: B θ'' = −w (l − s) cos θ, θ(0) = 0, θ'(l) = 0, θ the
/// slope below the horizontal. Returns the angle below the horizontal of the chord from the
/// clamp to the tip (shooting on θ'(0), RK4).
inline double elastica_chord_angle(double l_over_c) {
  const int steps = 4000;
  const double ds = l_over_c / steps;  // lengths in units of c
  auto shoot = [&](double kappa0, double& x, double& z) {
    double theta = 0.0, kappa = kappa0;
    x = z = 0.0;
    for (int k = 0; k < steps; ++k) {
      const double s = k * ds;
      auto rhs = [&](double sv, double th) { return -(l_over_c - sv) * std::cos(th); };
      const double k1t = kappa, k1k = rhs(s, theta);
      const double k2t = kappa + 0.5 * ds * k1k, k2k = rhs(s + 0.5 * ds, theta + 0.5 * ds * k1t);
      const double k3t = kappa + 0.5 * ds * k2k, k3k = rhs(s + 0.5 * ds, theta + 0.5 * ds * k2t);
      const double k4t = kappa + ds * k3k, k4k = rhs(s + ds, theta + ds * k3t);
      const double next = theta + ds / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
      x += 0.5 * ds * (std::cos(theta) + std::cos(next));
      z += 0.5 * ds * (std::sin(theta) + std::sin(next));
      theta = next;
      kappa += ds / 6.0 * (k1k + 2 * k2k + 2 * k3k + k4k);
    }
    return kappa;  // θ'(l)
  };
  double lo = 0.0, hi = 0.5 * l_over_c * l_over_c, x = 0.0, z = 0.0;
  for (int k = 0; k < 80; ++k) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid, x, z) < 0.0 ? lo : hi) = mid;
  }
  shoot(0.5 * (lo + hi), x, z);
  return std::atan2(z, x);
}

/// The simulated strip's chord angle at overhang l: a strip of width 2.5 cm, warp along its
/// length, two columns clamped on the platform (level at the edge), gravity raised in steps.
inline double simulated_chord_angle(const ClothMaterial& m, double overhang, double spacing, bool& converged,
                                    SheetBending bending = SheetBending::yarns) {
  converged = true;
  auto grid = rectangular_sheet(overhang + spacing, 0.025, spacing, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), bending);
  std::vector<std::int32_t> clamp;
  if (bending == SheetBending::yarns) {
    clamp = clamp_warp_start(grid);
  } else {  // hinges: the two held columns alone
    for (int j = 0; j < grid.nodes_v; ++j) clamp.insert(clamp.end(), {grid.at(0, j), grid.at(1, j)});
  }
  Body body;
  body.model = std::make_shared<ClothModel>(grid.cloth, m);
  body.settings.solver = LinearSolver::cholesky;
  body.fix_nodes(clamp);
  BodyState state = make_state(body);
  for (int k = 1; k <= 10; ++k) {
    body.gravity = Vec3(0.0, 0.0, -kGravity * k / 10.0);
    const auto r = solve_static(body, state, {}, StaticSettings{200, 1e-10, 1e-14});
    converged = converged && r.converged;
  }
  const Vec3 root = body.model->rest_positions().segment<3>(3 * grid.at(1, 0));
  const Vec3 tip = state.x.segment<3>(3 * grid.at(grid.nodes_u - 1, 0));
  return std::atan2(root.z() - tip.z(), tip.x() - root.x());
}

/// A square sheet of side `side` at 10 mm whose border is held on a picture frame.
struct PictureFrame {
  SheetGrid grid;
  Body body;
  std::vector<std::int32_t> border;
  PictureFrame(const ClothMaterial& m, double side) : grid(rectangular_sheet(side, side, 0.01)) {
    body.model = std::make_shared<ClothModel>(grid.cloth, m);
    body.settings.solver = LinearSolver::cholesky;
    for (int j = 0; j < grid.nodes_v; ++j)
      for (int i = 0; i < grid.nodes_u; ++i)
        if (i == 0 || j == 0 || i == grid.nodes_u - 1 || j == grid.nodes_v - 1) border.push_back(grid.at(i, j));
    body.fix_nodes(border);
  }
  /// Where (u, v) of the fabric lies on the frame sheared by `angle`.
  [[nodiscard]] static Vec3 sheared(const Vec2& uv, double angle) {
    return {uv.x() + std::sin(angle) * uv.y(), std::cos(angle) * uv.y(), 0.0};
  }
};

/// The picture frame: a square sheet of side `side` whose border follows a frame sheared by γ
/// (sides keep their length, the corner angle closes by γ), the inside free. Returns the
/// frame's generalized force dE/dγ (central difference of the equilibrium energy), which the
/// shear curve says is side²·T_s(γ).
inline double picture_frame_force(const ClothMaterial& m, double side, double gamma, bool& converged) {
  converged = true;
  PictureFrame frame(m, side);
  auto energy_at = [&](double angle) {
    BodyState state = make_state(frame.body);
    for (Eigen::Index n = 0; n < state.x.size() / 3; ++n)
      state.x.segment<3>(3 * n) = PictureFrame::sheared(frame.grid.cloth.uv[static_cast<std::size_t>(n)], angle);
    const auto r = solve_static(frame.body, state, {}, StaticSettings{100, 1e-10, 1e-12});
    converged = converged && r.converged;
    return frame.body.model->elastic_energy(state.x, state.q);
  };
  const double h = 1e-5;
  return (energy_at(gamma + h) - energy_at(gamma - h)) / (2 * h);
}

/// The KES shear test on the picture frame: the frame sheared quasi-statically 0 → +γ_max →
/// −γ_max → +γ_max in steps of `step`, the sheet balanced at each and its stick angles then
/// following (update_internal, as at the end of a time step). Returns the force the frame
/// needs, dE/dγ as virtual work of the balanced sheet's forces, −Σ f_n·∂x_n/∂γ, while it moves
/// (before the stick angles follow), at angle `at` on the way down from +γ_max and on the way
/// back up from −γ_max. `at` and γ_max must be multiples of `step`.
inline std::pair<double, double> picture_frame_loop(const ClothMaterial& m, double side, double gamma_max, double step,
                                                    double at, bool& converged) {
  converged = true;
  PictureFrame frame(m, side);
  const Body& body = frame.body;
  const SheetGrid& grid = frame.grid;
  BodyState state = make_state(body);
  auto frame_force = [&](double angle) {
    VecX f(state.x.size());
    body.model->forces(state.x, VecX::Zero(state.x.size()), state.q, f, *state.model_scratch);
    double work = 0.0;
    for (std::size_t n = 0; n < grid.cloth.uv.size(); ++n) {
      const double v = grid.cloth.uv[n].y();
      work -= f.segment<3>(3 * static_cast<Eigen::Index>(n)).dot(Vec3(std::cos(angle) * v, -std::sin(angle) * v, 0.0));
    }
    return work;
  };
  const auto steps = static_cast<int>(std::lround(gamma_max / step));
  const auto at_step = static_cast<int>(std::lround(at / step));
  double down = 0.0, up = 0.0;
  auto go = [&](int from, int to, double* record) {
    const int dir = to > from ? 1 : -1;
    for (int k = from + dir; k != to + dir; k += dir) {
      const double angle = k * step;
      for (std::int32_t n : frame.border)
        state.x.segment<3>(3 * n) = PictureFrame::sheared(grid.cloth.uv[static_cast<std::size_t>(n)], angle);
      const auto r = solve_static(body, state, {}, StaticSettings{100, 1e-10, 1e-12});
      converged = converged && r.converged;
      if (record && k == at_step) *record = frame_force(angle);
      body.model->update_internal(state.x, 1.0, state.q, *state.model_scratch);
    }
  };
  go(0, steps, nullptr);
  go(steps, -steps, &down);
  go(-steps, steps, &up);
  return {down, up};
}

/// Peirce's bending length read as the standard reads it: the overhang at which the chord
/// from the platform's edge to the tip falls 41.5° below the horizontal, halved (bisection
/// between `lo` and `hi`).
inline double peirce_bending_length(const ClothMaterial& m, double spacing, double lo, double hi, bool& converged,
                                    SheetBending bending = SheetBending::yarns) {
  converged = true;
  const double deg = 180.0 / 3.14159265358979323846;
  for (int k = 0; k < 12; ++k) {
    const double mid = 0.5 * (lo + hi);
    bool ok = false;
    (simulated_chord_angle(m, mid, spacing, ok, bending) * deg < 41.5 ? lo : hi) = mid;
    converged = converged && ok;
  }
  return 0.25 * (lo + hi);
}

}  // namespace tactus::physics::fabric_lab
