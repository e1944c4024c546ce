#pragma once
// Generalized Maxwell (Prony series) relaxation of a stress per element: the small-strain or
// corotated stress of the linear laws, the second Piola-Kirchhoff stress of the hyperelastic ones.
// Internal variables per element: the reference stress sbar_n of the last step end, then one
// branch stress h_i per term, each a symmetric 3x3 stored as xx yy zz xy yz zx.
#include <span>
#include <vector>

#include "core/math.hpp"
#include "physics/fem/material.hpp"

namespace tactus::physics {

/// Internal variables one element needs for `terms` Prony terms.
inline std::size_t prony_size(std::size_t terms) { return terms == 0 ? 0 : 6 * (terms + 1); }

/// Stress the Maxwell branches add to the instantaneous elastic stress sbar(x) during a step:
/// sum_i (h_i - g_i sbar_n). Within a step the branches respond with their instantaneous
/// stiffness; their dashpots relax only in prony_update, so K stays the elastic tangent.
Mat3 prony_offset(const std::vector<PronyTerm>& terms, std::span<const double> q);

/// The reference stress sbar_n stored in an element's internal variables.
Mat3 prony_reference(std::span<const double> q);

/// Advances the branches over dt to the new reference stress sbar (Simo & Hughes 1998, eq.
/// 10.3.9): h_i <- exp(-dt/tau_i) h_i + g_i (1 - exp(-dt/tau_i)) / (dt/tau_i) (sbar - sbar_n),
/// exact for a strain that varies linearly over the step; then sbar_n <- sbar.
void prony_update(const std::vector<PronyTerm>& terms, const Mat3& sbar, double dt, std::span<double> q);

}  // namespace tactus::physics
