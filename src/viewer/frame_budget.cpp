#include "viewer/frame_budget.hpp"

#include <algorithm>
#include <cmath>

namespace tactus::viewer {

bool is_software_renderer(std::string_view gl_renderer) {
  for (const std::string_view name : {"llvmpipe", "softpipe", "swrast", "SWR", "Software Rasterizer"})
    if (gl_renderer.find(name) != std::string_view::npos) return true;
  return false;
}

ResolutionGovernor::ResolutionGovernor(const Settings& settings) : settings_(settings) {
  window_.reserve(settings_.period);
}

void ResolutionGovernor::add(double frame_ms) {
  if (!std::isfinite(frame_ms) || frame_ms < 0.0) return;
  window_.push_back(frame_ms);
  if (window_.size() < std::max<std::size_t>(settings_.period, 1)) return;
  // The median of the window: one frame stalled by the scheduler does not shrink the picture.
  std::nth_element(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(window_.size() / 2), window_.end());
  const double typical = window_[window_.size() / 2];
  window_.clear();
  const double aim = settings_.target * settings_.budget_ms;
  double next = scale_;
  if (typical > settings_.budget_ms)
    next = scale_ * std::sqrt(aim / typical);
  else if (typical < settings_.grow_below * settings_.budget_ms)
    next = scale_ * std::min(std::sqrt(aim / std::max(typical, 1e-3)), 1.25);
  scale_ = std::clamp(next, settings_.min_scale, 1.0);
}

}  // namespace tactus::viewer
