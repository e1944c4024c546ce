#pragma once
// What a configuration space is built from: the grid around the organ, the contact node
// (or patch) that is moved to each grid point, and the solver's convergence criteria.
// docs/scene-format.md ([precompute]) documents each field as the key that sets it.
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
};

}  // namespace tactus::precompute
