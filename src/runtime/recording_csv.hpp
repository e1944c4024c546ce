#pragma once
// A recording as CSV, one table per record kind (columns in docs/recording-format.md).
// Doubles are written in their shortest form that reads back to the same value.
#include <ostream>

#include "runtime/recording.hpp"

namespace tactus::runtime {

/// t, device, frame, x, y, z, qw, qx, qy, qz, buttons, fx, fy, fz, tx, ty, tz, contact,
/// flags, proxy_x, proxy_y, proxy_z, compute_us, late_us.
void write_frames_csv(const Recording& recording, std::ostream& out);
/// t, step, compute_us, solver_iterations, late_us.
void write_steps_csv(const Recording& recording, std::ostream& out);
/// t, kind, device, value, text.
void write_events_csv(const Recording& recording, std::ostream& out);

}  // namespace tactus::runtime
