#pragma once
// What a configuration space is built from: the grid around the organ, the contact node
// (or patch) that is moved to each grid point, and the solver's convergence criteria.
// docs/scene-format.md ([precompute]) documents each field as the key that sets it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.hpp"

namespace tactus::precompute {

/// How forces and shapes are interpolated between grid points (docs/precompute.md).
/// The last two use the derivatives stored with each configuration (Hermite interpolation).
enum class Interpolation { trilinear, rbf_cubic, rbf_thin_plate, polynomial, tricubic_hermite, rbf_hermite };

/// Parses a method's name (to_string's); throws InputError naming the alternatives otherwise.
Interpolation parse_interpolation(std::string_view name);
std::string_view to_string(Interpolation method);

/// A probe space (docs/precompute.md, "Probe spaces"): the patch is the end of a rigid probe,
/// bonded to it, and the probe may lean away from its rest axis. Each level of the space is a
/// grid of configurations at one lean; the levels form a square lattice of `tilt_levels` ×
/// `tilt_levels` leans over [−max_tilt, max_tilt]² (precompute/probe.hpp).
struct ProbeSettings {
  Vec3 axis = Vec3::Zero();  ///< the probe's rest direction, pointing into the body (unit)
  double max_tilt = 0.0;     ///< [rad] the largest lean the space covers about each tangent axis
  int tilt_levels = 1;       ///< leans per tangent axis (odd; 1: a point space, no probe)
  [[nodiscard]] bool enabled() const { return tilt_levels > 1; }
  [[nodiscard]] std::size_t level_count() const {
    return static_cast<std::size_t>(tilt_levels) * static_cast<std::size_t>(tilt_levels);
  }
};

/// A two-point space (docs/precompute.md, "Two-point spaces"): a second interaction point (a
/// second finger or instrument) with its own patch and grid box, on the space's spacing. Seed
/// 001 (§3.4): "each degree of freedom yields additional dimension of the grid". The space is
/// built as levels (precompute/pair.hpp): each point's space with the other free, then for
/// each grid point of the other, its space with the other held there.
struct PairSettings {
  std::int32_t node = -1;                 ///< the other point's contact node (−1: no other point)
  std::vector<std::int32_t> patch_nodes;  ///< moved rigidly with it (sorted, contains node)
  Vec3 bounds_min = Vec3::Zero();         ///< its grid covers this box [m]
  Vec3 bounds_max = Vec3::Zero();
  [[nodiscard]] bool enabled() const { return node >= 0; }
};

struct SpaceSettings {
  std::string body;                   ///< scene body the space belongs to
  std::int32_t contact_node = 0;      ///< the interaction point: a node of the body's volume mesh
  /// Nodes moved rigidly with the contact node (sorted, contains contact_node).
  std::vector<std::int32_t> patch_nodes;
  double patch_radius = 0.0;          ///< [m] patch = nodes within this rest distance
  double spacing = 0.02;              ///< d_G [m]
  Vec3 bounds_min = Vec3::Zero();     ///< the grid covers this box [m]
  Vec3 bounds_max = Vec3::Zero();
  int load_steps = 2;                 ///< load steps per transition (one grid edge)
  /// A load step whose Newton solve fails is retried from the last converged state in halves,
  /// at most this many times per load step (down to 2^-n of it) before the point fails.
  int max_step_halvings = 4;
  int max_iterations = 50;            ///< Newton iterations per load step
  double tolerance = 1e-8;            ///< relative residual per load step
  bool gravity = false;               ///< configurations include the body's weight
  /// Adaptive refinement after the build: at most this many points more (0: none).
  int refine_points = 0;
  Interpolation interpolation = Interpolation::trilinear;
  ProbeSettings probe;
  /// This level's lean of the probe [rad] (its tangent coordinates; zero without a probe).
  Vec2 tilt = Vec2::Zero();
  /// A second interaction point held still in every configuration (a second finger): the
  /// node (−1: none) and where it is held [m]. The start point moves it there from rest. Its
  /// patch (sorted, contains held_node; empty: the node alone) moves rigidly with it.
  std::int32_t held_node = -1;
  Vec3 held_at = Vec3::Zero();
  std::vector<std::int32_t> held_patch;
  /// A two-point space: the other point (the contact node and patch above are this level's
  /// own), and which of the scene's two points this level's own is (0: contact_point, 1:
  /// second_point).
  PairSettings pair;
  int finger = 0;
};

}  // namespace tactus::precompute
