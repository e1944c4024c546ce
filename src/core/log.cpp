#include "core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace tactus::log {

void init(Level level) {
  static auto logger = [] {
    auto l = spdlog::stderr_color_mt("tactus");
    l->set_pattern("%^[%l]%$ %v");
    spdlog::set_default_logger(l);
    return l;
  }();
  switch (level) {
    case Level::quiet: logger->set_level(spdlog::level::err); break;
    case Level::warn: logger->set_level(spdlog::level::warn); break;
    case Level::info: logger->set_level(spdlog::level::info); break;
    case Level::debug: logger->set_level(spdlog::level::debug); break;
  }
}

}  // namespace tactus::log
