#pragma once
// The end-of-run summary of a needle insertion: which layers tore, in what order, at what
// force (against their thresholds), and how far the tip strayed from the planned path.
#include <cstddef>
#include <string>
#include <vector>

#include "haptics/algorithms/needle.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

struct NeedleRuptureReport {
  std::string layer;      ///< the layer's body
  double t = 0.0;         ///< [s]
  double force = 0.0;     ///< spring force when it tore [N]
  double threshold = 0.0; ///< the layer's rupture_force [N]
};

struct NeedleReport {
  std::string device;
  std::size_t layers = 0;                    ///< layers the needle may pierce
  bool touched = false;                      ///< the tip ever pressed on a layer
  std::vector<NeedleRuptureReport> ruptures;  ///< in the order they happened
  bool planned = false;        ///< deviations are from the planned path (else the puncture path)
  double max_deviation = 0.0;  ///< [m]
  double last_deviation = 0.0; ///< [m]
};

[[nodiscard]] NeedleReport needle_report(const scene::Model& model, const std::string& device,
                                         const haptics::NeedleInsertion& needle);
[[nodiscard]] std::string format_needle_report(const NeedleReport& report);
[[nodiscard]] std::string needle_report_json(const NeedleReport& report);

}  // namespace tactus::runtime
