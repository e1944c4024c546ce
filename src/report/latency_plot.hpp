#pragma once
// The loops' latency histograms as a PNG (`tactus bench --plot`): one panel per loop, the
// share of its steps by compute time (and, in real time, by start-to-start period) on a
// logarithmic time axis, with its nominal period marked.
#include <filesystem>
#include <vector>

#include "runtime/loop_stats.hpp"

namespace tactus::report {

/// Writes the plot; InputError naming the file where it cannot be written, or where there
/// is no loop with a step to plot.
void write_latency_plot(const std::filesystem::path& path, const std::vector<runtime::LoopStats>& loops,
                        bool real_time);

}  // namespace tactus::report
