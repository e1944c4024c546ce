#include "precompute/configuration_solver.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <string>
#include <fmt/format.h>
#include <stdexcept>

#include "core/error.hpp"
#include "precompute/probe.hpp"

namespace tactus::precompute {

ConfigurationSolver::ConfigurationSolver(const physics::Body& body, const SpaceSettings& settings)
    : body_(body), settings_(settings) {
  const auto nodes = body_.model->node_count();
  if (settings_.patch_nodes.empty()) settings_.patch_nodes = {settings_.contact_node};
  body_.fixed_dofs.resize(3 * nodes, 0);
  for (auto n : settings_.patch_nodes) {
    if (n < 0 || static_cast<std::size_t>(n) >= nodes)
      throw InputError(fmt::format("contact patch node {} is not a node of the body ({} nodes)", n, nodes));
    if (body_.fixed_dofs[3 * static_cast<std::size_t>(n)])
      throw InputError(fmt::format("contact patch node {} lies in a fixed region; choose another contact point", n));
  }
  body_.fix_nodes(settings_.patch_nodes);
  if (settings_.held_node >= 0) {
    if (settings_.held_patch.empty()) settings_.held_patch = {settings_.held_node};
    if (!std::binary_search(settings_.held_patch.begin(), settings_.held_patch.end(), settings_.held_node))
      throw InputError(fmt::format("the held patch does not hold its node {}", settings_.held_node));
    for (auto n : settings_.held_patch)
      if (n < 0 || static_cast<std::size_t>(n) >= nodes || body_.fixed_dofs[3 * static_cast<std::size_t>(n)] ||
          !settings_.held_at.allFinite())
        throw InputError(fmt::format("the second interaction point's node {} is not a free node of the body, apart "
                                     "from the contact patch",
                                     n));
    body_.fix_nodes(settings_.held_patch);
  }
  body_.settings.solver = physics::LinearSolver::cholesky;
  if (!settings_.gravity) body_.gravity = Vec3::Zero();
  contact_rest_ = body_.model->rest_positions().segment<3>(3 * static_cast<Eigen::Index>(settings_.contact_node));
  rotation_ = probe_rotation(settings_);
  state_ = physics::make_state(body_);
  force_ = VecX::Zero(state_.x.size());
}

void ConfigurationSolver::place_patch(const Pose& pose) {
  const VecX& rest = body_.model->rest_positions();
  if (settings_.held_node >= 0) {
    // The held patch moves rigidly with its node.
    const auto node = 3 * static_cast<Eigen::Index>(settings_.held_node);
    const Vec3 shift = pose.held * (settings_.held_at - rest.segment<3>(node));
    for (auto n : settings_.held_patch) {
      const auto i = 3 * static_cast<Eigen::Index>(n);
      state_.x.segment<3>(i) = rest.segment<3>(i) + shift;
    }
  }
  if (pose.rotation.isZero(0.0)) {
    const Vec3 shift = pose.contact - contact_rest_;
    for (auto n : settings_.patch_nodes) {
      const auto i = 3 * static_cast<Eigen::Index>(n);
      state_.x.segment<3>(i) = rest.segment<3>(i) + shift;
    }
    return;
  }
  const double angle = pose.rotation.norm();
  const Mat3 turn = Eigen::AngleAxisd(angle, pose.rotation / angle).toRotationMatrix();
  for (auto n : settings_.patch_nodes) {
    const auto i = 3 * static_cast<Eigen::Index>(n);
    state_.x.segment<3>(i) = pose.contact + turn * (rest.segment<3>(i) - contact_rest_);
  }
}

void ConfigurationSolver::reaction(PointResult& r) {
  body_.model->forces(state_.x, state_.v, state_.q, force_, *state_.model_scratch);
  const VecX& mass = body_.model->lumped_mass();
  const Vec3 contact = state_.x.segment<3>(3 * static_cast<Eigen::Index>(settings_.contact_node));
  r.force.setZero();
  r.torque.setZero();
  for (auto n : settings_.patch_nodes) {
    const auto i = 3 * static_cast<Eigen::Index>(n);
    Vec3 f = force_.segment<3>(i);
    if (settings_.gravity) f += mass.segment<3>(i).cwiseProduct(body_.gravity);
    r.force += f;
    r.torque += (state_.x.segment<3>(i) - contact).cross(f);
  }
}

bool ConfigurationSolver::derivatives(PointResult& r) {
  // The patch moves rigidly with the interaction point: a unit move along axis k moves
  // every patch node by e_k.
  held_.setZero(state_.x.size(), 3);
  for (auto n : settings_.patch_nodes)
    held_.block<3, 3>(3 * static_cast<Eigen::Index>(n), 0).setIdentity();
  if (!physics::static_response(body_, state_, held_, r.displacement_gradient, force_change_)) return false;
  // The reaction sums the patch nodes' internal forces (gravity does not move). The patch
  // translates, so each node's lever about the contact node stays: the torque changes by the
  // levers crossed with the forces' changes.
  r.force_gradient.setZero();
  r.torque_gradient.setZero();
  const Vec3 contact = state_.x.segment<3>(3 * static_cast<Eigen::Index>(settings_.contact_node));
  for (auto n : settings_.patch_nodes) {
    const auto i = 3 * static_cast<Eigen::Index>(n);
    const auto change = force_change_.block<3, 3>(i, 0);
    r.force_gradient += change;
    const Vec3 lever = state_.x.segment<3>(i) - contact;
    for (int k = 0; k < 3; ++k) r.torque_gradient.col(k) += lever.cross(Vec3(change.col(k)));
  }
  return r.force_gradient.allFinite() && r.torque_gradient.allFinite();
}

PointResult ConfigurationSolver::solve_start(std::size_t point, const Vec3& target) {
  // A leaning probe turns the patch from rest, and a held second point moves there from rest:
  // deformations, walked in load steps.
  const bool moves = !rotation_.isZero(0.0) || settings_.held_node >= 0;
  return run(point, -1, nullptr, {contact_rest_, Vec3::Zero(), 0.0}, {target, rotation_, 1.0},
             moves ? settings_.load_steps : 1);
}

PointResult ConfigurationSolver::transition(std::size_t point, std::int64_t source, const VecX& source_displacement,
                                            const Vec3& from, const Vec3& target) {
  return run(point, source, &source_displacement, {from, rotation_}, {target, rotation_}, settings_.load_steps);
}

PointResult ConfigurationSolver::solve_direct(const Vec3& target, int steps) {
  return solve_direct(target, rotation_, steps);
}

PointResult ConfigurationSolver::solve_direct(const Vec3& target, const Vec3& rotation, int steps) {
  return run(0, -1, nullptr, {contact_rest_, Vec3::Zero(), 0.0}, {target, rotation, 1.0}, steps);
}

PointResult ConfigurationSolver::run(std::size_t point, std::int64_t source, const VecX* start, const Pose& from,
                                     const Pose& target, int steps) {
  const auto t0 = std::chrono::steady_clock::now();
  PointResult r;
  r.point = point;
  r.source = source;
  const VecX& rest = body_.model->rest_positions();
  // Every solve starts from the same state whatever this solver did before, so a point's
  // result depends only on its source (any worker, any rank, any order gives the same bits).
  state_.x = start ? VecX(rest + *start) : rest;
  state_.v.setZero();
  state_.q.setZero();
  physics::forget_solver_history(state_);
  r.status = PointStatus::solved;
  // The path from `from` to `target` is walked in fractions of it. A step whose solve fails
  // is retried from the last converged state at half the size (a shorter step starts
  // Newton closer to its solution), at most max_step_halvings times per load step; the step
  // stays refined for the rest of its load step, so the step never falls below
  // 2^-max_step_halvings of the nominal one and the walk ends. Deterministic: the same inputs
  // refine the same way on any worker.
  const double nominal = 1.0 / steps;
  VecX converged = state_.x;
  double reached = 0.0;
  for (int s = 1; s <= steps && r.status == PointStatus::solved; ++s) {
    const double end = s == steps ? 1.0 : static_cast<double>(s) / steps;
    double step = nominal;
    int halvings = 0;
    while (reached < end && r.status == PointStatus::solved) {
      const double fraction = std::min(end, reached + step);
      place_patch({from.contact + fraction * (target.contact - from.contact),
                   from.rotation + fraction * (target.rotation - from.rotation),
                   from.held + fraction * (target.held - from.held)});
      std::string failure;
      double step_residual = 0.0;
      try {
        // The free nodes follow the patch from the last equilibrium before Newton starts, so
        // a long step does not begin with the patch's elements inside out.
        physics::predict_static(body_, state_, converged);
        const physics::StaticSettings newton{settings_.max_iterations, settings_.tolerance, kAbsoluteForceTolerance};
        const auto res = physics::solve_static(body_, state_, {}, newton);
        r.iterations += res.iterations;
        step_residual = res.residual;
        if (res.inverted)
          failure = fmt::format("the balanced state has an element inside out (min volume ratio {:.3g})",
                                body_.model->min_volume_ratio(state_.x));
        else if (!res.converged)
          failure = fmt::format("{} at relative residual {:.3g} ({:.3g} N) after {} Newton iterations",
                                res.stagnated ? "line search stagnated" : "no convergence", res.residual,
                                res.residual_force, res.iterations);
        else if (!state_.x.allFinite())
          failure = "non-finite positions";
      } catch (const std::runtime_error& e) {
        failure = e.what();
      }
      if (failure.empty()) {
        r.residual = std::max(r.residual, step_residual);
        reached = fraction;
        converged = state_.x;
      } else if (halvings < settings_.max_step_halvings) {
        ++halvings;
        ++r.refinements;
        step *= 0.5;
        state_.x = converged;
      } else {
        r.status = PointStatus::failed;
        r.residual = std::max(r.residual, step_residual);
        r.reason = halvings == 0 ? fmt::format("load step {}/{}: {}", s, steps, failure)
                                 : fmt::format("load step {}/{} (after {} halvings, step {:.3g} of the path): {}", s,
                                               steps, halvings, step, failure);
      }
    }
  }
  newton_iterations_ += r.iterations;
  if (r.status == PointStatus::solved) {
    reaction(r);
    if (!r.force.allFinite() || !r.torque.allFinite()) {
      r.status = PointStatus::failed;
      r.reason = "non-finite reaction force";
      r.force.setZero();
      r.torque.setZero();
    } else if (const auto d0 = std::chrono::steady_clock::now(); !derivatives(r)) {
      r.status = PointStatus::failed;
      r.reason = "the balanced state's stiffness could not be solved for the derivatives";
      r.force.setZero();
      r.torque.setZero();
    } else {
      r.derivative_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - d0).count();
      r.displacement = state_.x - rest;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace tactus::precompute
