// How far the hand's predicted position one simulation step ahead (seed 002 §IV) lands from
// where the hand went, over recorded runs: per device, the median, p99 and largest error of
// holding the last position, of a line and of a parabola fitted over the last 10 ms.
//   motion_prediction_error HORIZON_S FILE.tacrec...
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "haptics/motion_prediction.hpp"
#include "runtime/recording_reader.hpp"

using namespace tactus;

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s HORIZON_S FILE.tacrec...\n", argv[0]);
    return 1;
  }
  const double horizon = std::atof(argv[1]);
  std::printf("| recording | device | frames | hold: median / p99 / max µm | line | parabola |\n|---|---|---|---|---|---|\n");
  for (int a = 2; a < argc; ++a) {
    const runtime::Recording rec = runtime::read_recording(argv[a]);
    std::map<int, std::vector<const runtime::HapticFrame*>> by_device;
    for (const auto& f : rec.frames) by_device[f.device].push_back(&f);
    for (const auto& [device, frames] : by_device) {
      haptics::MotionPredictor line(haptics::Extrapolation::linear), parabola(haptics::Extrapolation::quadratic);
      std::vector<double> e_hold, e_line, e_parabola;
      std::size_t ahead = 0;
      for (std::size_t k = 0; k < frames.size(); ++k) {
        const auto& f = *frames[k];
        line.add(f.t, f.position);
        parabola.add(f.t, f.position);
        while (ahead < frames.size() && frames[ahead]->t < f.t + horizon - 1e-9) ++ahead;
        if (ahead >= frames.size() || k < 20) continue;
        const Vec3 truth = frames[ahead]->position;
        const double dt = frames[ahead]->t - f.t;
        e_hold.push_back(1e6 * (f.position - truth).norm());
        e_line.push_back(1e6 * (line.predict(dt) - truth).norm());
        e_parabola.push_back(1e6 * (parabola.predict(dt) - truth).norm());
      }
      auto cell = [](const std::vector<double>& e) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.1f / %.1f / %.1f", percentile(e, 0.5), percentile(e, 0.99),
                      e.empty() ? 0.0 : *std::max_element(e.begin(), e.end()));
        return std::string(buf);
      };
      const auto& names = rec.header.devices;
      const std::string name = static_cast<std::size_t>(device) < names.size() ? names[static_cast<std::size_t>(device)] : std::to_string(device);
      std::printf("| %s | %s | %zu | %s | %s | %s |\n", argv[a], name.c_str(), e_hold.size(), cell(e_hold).c_str(),
                  cell(e_line).c_str(), cell(e_parabola).c_str());
    }
  }
  return 0;
}
