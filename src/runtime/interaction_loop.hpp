#pragma once
// The interaction loop step: for every device, find where its tool is closest to the
// newest deformed surfaces and publish that as the device's local contact model (a plane
// through the closest point), which the haptic loop renders until the next one.
#include <memory>
#include <string>
#include <vector>

#include "contact/bvh.hpp"
#include "mesh/curvature.hpp"
#include "core/triple_buffer.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/loop_stats.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

struct InteractionTarget {
  DeviceChannels* channels = nullptr;
  std::string device;  ///< the device's name, for the timing report
  std::vector<std::size_t> bodies;  ///< bodies this device's algorithm touches
  double reach = 0.0;  ///< a surface farther than this from the tool origin gives no contact [m]
  /// q-ring size of the curvature vote at the contact point; 0 = no curvature needed.
  int curvature_rings = 0;
  /// > 0: a needle this long [m]; `bodies` are its layers, and instead of a closest point
  /// the loop publishes where the needle's line crosses each layer (DeviceChannels::needle).
  double needle_length = 0.0;
};

class InteractionLoop {
 public:
  InteractionLoop(const scene::Model& model, std::vector<InteractionTarget> targets,
                  TripleBuffer<SurfaceSnapshot>& surfaces);

  void step(double t, Nanos deadline, Nanos start, bool real_time);

  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// Per device: one body's collision query ("<device>: query per body", seed 003 Table 1's
  /// CD), and the device's whole handling in a step ("<device>: interaction", its IN); then
  /// "refit trees" (the trees' update after a simulation step, its updateGeo).
  [[nodiscard]] const std::vector<PartStats>& parts() const { return parts_; }

 private:
  const scene::Model& model_;
  std::vector<InteractionTarget> targets_;
  TripleBuffer<SurfaceSnapshot>& surfaces_;
  /// One tree per body, refitted to every new simulation step (rebuilt when refits have
  /// degraded it), so a query costs about a microsecond instead of a pass over the surface.
  std::vector<contact::TriangleBvh> trees_;
  std::uint64_t tree_step_ = ~std::uint64_t{0};
  /// Per target and body: the curvature estimator, when the target's algorithm needs one
  /// and the body's surface is a manifold.
  std::vector<std::vector<std::unique_ptr<mesh::CurvatureEstimator>>> curvature_;
  void publish_needle_crossings(std::size_t k, const InteractionTarget& target, const ToolState& tool);

  LoopStats stats_;
  std::vector<PartStats> parts_;
  std::vector<contact::RayHit> hits_;  ///< reused by the needle queries
};

}  // namespace tactus::runtime
