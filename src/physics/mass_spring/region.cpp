#include "physics/mass_spring/region.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tactus::physics {

std::vector<std::int32_t> nodes_outside_radius(const VecX& x, const Vec3& center, double radius) {
  if (!(radius >= 0.0)) throw InputError("region: radius must be >= 0");
  std::vector<std::int32_t> out;
  const double r2 = radius * radius;
  for (Eigen::Index n = 0; 3 * n + 2 < x.size(); ++n)
    if ((x.segment<3>(3 * n) - center).squaredNorm() > r2) out.push_back(static_cast<std::int32_t>(n));
  return out;
}

Body restrict_to_region(const Body& full, const SpringNetwork& network, const VecX& x, const Vec3& center,
                        double radius) {
  if (full.model.get() != &network) throw InputError("region: the network must be the body's model");
  const std::size_t nodes = network.node_count();
  Body out = full;
  out.fixed_dofs.resize(3 * nodes, 0);
  for (auto n : nodes_outside_radius(x, center, radius))
    for (std::size_t k = 0; k < 3; ++k) out.fixed_dofs[3 * static_cast<std::size_t>(n) + k] = 1;
  // A spring can be dropped only when all six of its dofs are fixed.
  std::vector<std::uint8_t> node_fixed(nodes, 0);
  for (std::size_t n = 0; n < nodes; ++n)
    node_fixed[n] = out.fixed_dofs[3 * n] && out.fixed_dofs[3 * n + 1] && out.fixed_dofs[3 * n + 2];
  out.model = network.restricted(node_fixed);
  return out;
}

void rebind_state(const Body& body, BodyState& state) {
  state.model_scratch = body.model->make_scratch();
  state.solver_scratch.reset();  // the integrator rebuilds its free-dof mask on the next step
  for (std::size_t i = 0; i < body.fixed_dofs.size(); ++i)
    if (body.fixed_dofs[i]) state.v[static_cast<Eigen::Index>(i)] = 0.0;
}

}  // namespace tactus::physics
