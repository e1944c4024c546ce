#pragma once
// What seed 003 measures of its interaction scenarios (§4.4), from a run's timings: Table 1
// (collision query per object and hand, proximity search, interaction handling per hand,
// haptic frame, visual rate) and Fig. 10 (the simulation step split into solver, mapped
// surface updates and collision geometry updates), each as mean and standard deviation; and
// the force-magnitude traces of its Figs. 7–8.
#include <string>

#include "runtime/session.hpp"
#include "scene/model.hpp"

namespace tactus::report {

/// The Table 1 and Fig. 10 rows as text; `visual_rate` is the visual loop's mean rate and SD
/// [Hz] when one ran (negative: headless).
[[nodiscard]] std::string format_scenario_measures(const scene::Model& model, const runtime::SessionReport& report,
                                                   double visual_rate = -1.0, double visual_rate_sd = 0.0);

/// One row per kept frame (SessionOptions::keep_frames): `t,device,force,contact` with the
/// force magnitude sent to the device [N].
[[nodiscard]] std::string force_trace_csv(const scene::Model& model, const runtime::SessionReport& report);

/// One row per needle rupture: `t,device,layer,force,threshold`.
[[nodiscard]] std::string rupture_csv(const runtime::SessionReport& report);

/// One row per two-finger contact state that begins: `t,device,state` with the state's
/// numeral of seed 002 Table I (I–IX).
[[nodiscard]] std::string contact_state_csv(const scene::Model& model, const runtime::SessionReport& report);

}  // namespace tactus::report
