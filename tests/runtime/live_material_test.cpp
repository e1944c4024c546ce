// The live-edited body's model in direct implicit steps: reassembled from the scene model's
// values where no added damping follows its triplets, from triplets where it does; the same
// bits either way.
#include <gtest/gtest.h>

#include <memory>

#include "../physics/triplets_only.hpp"
#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/fem/tet_fem.hpp"
#include "runtime/live_parameters.hpp"

namespace tactus::runtime {
namespace {

VecX stepped(std::shared_ptr<const physics::ForceModel> model) {
  physics::Body body;
  body.model = std::move(model);
  body.settings.solver = physics::LinearSolver::cholesky;
  body.gravity = Vec3(0.0, 0.0, -9.81);
  body.fix_nodes({0, 1, 2, 3});
  physics::BodyState state = physics::make_state(body);
  for (int k = 0; k < 6; ++k) physics::step(body, state, 5e-3);
  return state.x;
}

TEST(LiveMaterialModel, DirectStepsAssembleTheSameBitsWithAndWithoutAddedDamping) {
  physics::FemMaterial material;
  material.law = physics::FemLaw::neo_hookean;
  material.young_modulus = 2e4;
  material.poisson_ratio = 0.4;
  material.density = 1000.0;
  material.rayleigh_mass = 1.0;
  const auto fem = std::make_shared<physics::TetFem>(mesh::box_volume(Vec3(0.04, 0.02, 0.02), 4, 2, 2), material);
  const VecX& m = fem->lumped_mass();
  for (double scene_damping : {0.0, 2.0}) {
    SCOPED_TRACE(scene_damping);
    // Stiffened by 1.3 with the scene's damping kept: no added damping where the scene has
    // none; where it has some, the scaled model's is made up by added damping.
    const auto live = std::make_shared<LiveMaterialModel>(fem, VecX::Constant(m.size(), scene_damping));
    live->set(1.3, -1.0);
    const VecX direct = stepped(live);
    EXPECT_EQ(direct, stepped(std::make_shared<physics::testing::TripletsOnly>(live)));
    EXPECT_GT((direct - fem->rest_positions()).norm(), 1e-6);
  }
}

}  // namespace
}  // namespace tactus::runtime
