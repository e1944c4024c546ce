#pragma once
// The timing table a run ends with (modelled on seed 003's Table 1 and Fig. 10: haptic
// frame time, simulation step time and its parts, per-object collision query time, rates),
// as text for people and as JSON for scripts.
#include <string>

#include "runtime/session.hpp"

namespace tactus::report {

[[nodiscard]] std::string format_report(const runtime::SessionReport& report);
[[nodiscard]] std::string report_json(const runtime::SessionReport& report);

}  // namespace tactus::report
