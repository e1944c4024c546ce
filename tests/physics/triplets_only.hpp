#pragma once
// A force model as it would be without add_matrix_values: the direct solver assembles it
// from triplets every time. Tests compare it with the model itself.
#include <memory>
#include <utility>
#include <vector>

#include "physics/force_model.hpp"

namespace tactus::physics::testing {

/// The same model, but without add_matrix_values: the solver assembles from triplets every
/// time, as it does for every model that does not offer the values.
class TripletsOnly final : public ForceModel {
 public:
  explicit TripletsOnly(std::shared_ptr<const ForceModel> inner) : inner_(std::move(inner)) {}
  [[nodiscard]] std::size_t node_count() const override { return inner_->node_count(); }
  [[nodiscard]] const VecX& rest_positions() const override { return inner_->rest_positions(); }
  [[nodiscard]] const VecX& lumped_mass() const override { return inner_->lumped_mass(); }
  [[nodiscard]] bool mass_is_diagonal() const override { return inner_->mass_is_diagonal(); }
  void add_mass_product(double scale, const VecX& in, VecX& out) const override {
    inner_->add_mass_product(scale, in, out);
  }
  void add_mass_triplets(double scale, std::vector<Triplet>& out) const override {
    inner_->add_mass_triplets(scale, out);
  }
  [[nodiscard]] std::size_t internal_size() const override { return inner_->internal_size(); }
  [[nodiscard]] std::unique_ptr<Scratch> make_scratch() const override { return inner_->make_scratch(); }
  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const override {
    inner_->forces(x, v, q, f, s);
  }
  void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override {
    inner_->linearize(x, v, q, s);
  }
  bool linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override {
    return inner_->linearize_exact(x, v, q, s);
  }
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const override {
    inner_->add_stiffness_product(dx, out, s);
  }
  void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const override {
    inner_->add_damping_product(dv, out, s);
  }
  void add_system_product(double a, double b, double c, const VecX& in, VecX& out, const Scratch& s) const override {
    inner_->add_system_product(a, b, c, in, out, s);
  }
  void add_diagonal(double a, double b, VecX& out, const Scratch& s) const override {
    inner_->add_diagonal(a, b, out, s);
  }
  const BlockMatrix* assemble_system(double a, double b, double c, Scratch& s) const override {
    return inner_->assemble_system(a, b, c, s);
  }
  void linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                         Scratch& s) const override {
    inner_->linearized_forces(x, v, q, dx, f, s);
  }
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const override {
    inner_->add_triplets(a, b, out, s);
  }
  void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const override {
    inner_->update_internal(x, dt, q, s);
  }
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override {
    return inner_->elastic_energy(x, q);
  }
  [[nodiscard]] double min_volume_ratio(const VecX& x) const override { return inner_->min_volume_ratio(x); }

 private:
  std::shared_ptr<const ForceModel> inner_;
};

}  // namespace tactus::physics::testing
