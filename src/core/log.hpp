#pragma once
// Logging goes through spdlog to stderr, so stdout stays for results.
#include <spdlog/spdlog.h>

namespace tactus::log {

enum class Level { quiet, warn, info, debug };

/// Sets up the stderr logger once; safe to call again to change the level.
void init(Level level);

using spdlog::debug;
using spdlog::error;
using spdlog::info;
using spdlog::warn;

}  // namespace tactus::log
