#include "vega_cloth.hpp"

#include <chrono>
#include <stdexcept>
#include <vector>

#include "clothBW.h"
#include "clothBWForceModel.h"
#include "implicitBackwardEulerSparse.h"

namespace vega_bench {
namespace {

/// The integrator with its system matrix and right-hand side in view (protected members).
class Integrator : public ImplicitBackwardEulerSparse {
 public:
  using ImplicitBackwardEulerSparse::ImplicitBackwardEulerSparse;
  SparseMatrix* system() { return systemMatrix; }
  const double* rhs() const { return bufferConstrained; }
};

}  // namespace

struct Cloth::Impl {
  std::unique_ptr<ClothBW> cloth;
  std::unique_ptr<ClothBWForceModel> model;
  SparseMatrix* mass = nullptr;
  std::unique_ptr<Integrator> integrator;
  std::unique_ptr<CGSolver> counter;
  std::vector<double> external, solution;
  int free_dofs = 0;
  ~Impl() { delete mass; }
};

Cloth::Cloth(const ClothSetup& s) : impl_(std::make_unique<Impl>()) {
  const int nodes = static_cast<int>(s.masses.size()), triangles = static_cast<int>(s.triangles.size() / 3);
  if (s.rest.size() != 3 * s.masses.size() || s.triangle_uv.size() != 6 * static_cast<std::size_t>(triangles) ||
      s.external.size() != s.rest.size())
    throw std::invalid_argument("vega cloth: array sizes do not match");
  ClothBW::MaterialGroup group{s.tensile, s.shear, s.bend_u, s.bend_v, 0.0};
  const std::vector<int> groups(static_cast<std::size_t>(triangles), 0);
  impl_->cloth = std::make_unique<ClothBW>(nodes, s.rest.data(), s.masses.data(), triangles, s.triangles.data(),
                                           s.triangle_uv.data(), groups.data(), 1, &group, 0);
  impl_->model = std::make_unique<ClothBWForceModel>(impl_->cloth.get());
  impl_->cloth->GenerateMassMatrix(&impl_->mass, 3);
  std::vector<int> fixed = s.fixed_dofs;
  impl_->integrator = std::make_unique<Integrator>(3 * nodes, s.dt, impl_->mass, impl_->model.get(),
                                                   static_cast<int>(fixed.size()), fixed.data(), s.damping_mass,
                                                   s.damping_stiffness, 1);
  impl_->external = s.external;
  impl_->integrator->SetExternalForces(impl_->external.data());
  impl_->free_dofs = 3 * nodes - static_cast<int>(fixed.size());
  impl_->solution.assign(static_cast<std::size_t>(impl_->free_dofs), 0.0);
}

Cloth::~Cloth() = default;

void Cloth::set_state(const std::vector<double>& u, const std::vector<double>& v) {
  std::vector<double> q = u, qvel = v;
  impl_->integrator->SetState(q.data(), qvel.data());
}

void Cloth::step() { impl_->integrator->DoTimestep(); }

double Cloth::force_time() const { return impl_->integrator->GetForceAssemblyTime(); }
double Cloth::solve_time() const { return impl_->integrator->GetSystemSolveTime(); }

int Cloth::resolve(double tolerance, double& seconds) {
  if (!impl_->counter) impl_->counter = std::make_unique<CGSolver>(impl_->integrator->system());
  std::fill(impl_->solution.begin(), impl_->solution.end(), 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  const int it = impl_->counter->SolveLinearSystemWithJacobiPreconditioner(impl_->solution.data(),
                                                                           impl_->integrator->rhs(), tolerance, 10000);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return it < 0 ? -it : it;
}

const double* Cloth::displacements() const { return impl_->integrator->Getq(); }
const double* Cloth::velocities() const { return impl_->integrator->Getqvel(); }

}  // namespace vega_bench
