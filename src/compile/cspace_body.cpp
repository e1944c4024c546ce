#include "compile/cspace_body.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "precompute/builder.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/space_file.hpp"
#include "compile/bodies.hpp"

namespace tactus::compile {

std::shared_ptr<const CspaceBody> CspaceBody::load(const scene::Model& model, std::size_t index) {
  const scene::Body& b = model.bodies.at(index);
  if (!b.cspace) throw InputError(fmt::format("body '{}' is not a cspace body", b.name));
  if (b.cspace->online) {
    if (!model.precompute || model.precompute->body != b.name)
      throw InputError(SourceLocation{model.source, {}, {}, {}},
                       fmt::format("body '{}' is built on-line (online = true) from the scene's [precompute] table, "
                                   "and {}",
                                   b.name,
                                   model.precompute ? fmt::format("that table is for body '{}'", model.precompute->body)
                                                    : std::string("the scene has none")));
    if (model.precompute->probe.enabled() || model.precompute->pair.enabled())
      throw InputError(SourceLocation{model.source, {}, {}, {}},
                       fmt::format("body '{}': on-line construction builds point spaces; the [precompute] table has "
                                   "{} (build it with `tactus precompute` and give the file as `space`)",
                                   b.name, model.precompute->probe.enabled() ? "a probe" : "a second point"));
    const physics::Body body = make_physics_body(model, index);
    precompute::Space space = precompute::make_space(body, *model.precompute, "");
    // The solvers' element loops run on their own thread: the parallelism is across points,
    // and the haptic thread keeps a core.
    set_thread_limit(1);
    auto factory = precompute::solver_transitions(body, *model.precompute, space.grid);
    VecX rest = space.rest_positions;
    auto online = std::make_unique<precompute::OnlineBuilder>(std::move(space), std::move(factory),
                                                              static_cast<unsigned>(b.cspace->workers));
    return std::make_shared<CspaceBody>(index, std::move(online), std::move(rest));
  }
  const auto& file = b.cspace->file;
  std::vector<std::shared_ptr<const precompute::Space>> levels;
  for (auto& level : precompute::read_space_levels(file))
    levels.push_back(std::make_shared<const precompute::Space>(std::move(level)));
  // The identity of this scene's body with the settings the space was built with: a space of
  // another mesh, material or fixed region, or a mesh edited since, is refused here.
  const physics::Body body = make_physics_body(model, index);
  for (const auto& space : levels) {
    if (space->identity.node_count != body.model->node_count())
      throw InputError(SourceLocation{file.string(), {}, {}, {}},
                       fmt::format("the space was built for a mesh of {} nodes; body '{}' has {}",
                                   space->identity.node_count, b.name, body.model->node_count()));
    precompute::check_identity(space->identity, precompute::identify(body, space->settings, space->grid),
                               file.string());
  }
  // A two-point space is felt by the two tools the body names; a space of one point by any.
  const bool two_points = levels.front()->settings.pair.enabled();
  if (two_points != (b.cspace->tools.size() == 2))
    throw InputError(SourceLocation{model.source, {}, {}, {}},
                     two_points ? fmt::format("body '{}': its space ({}) holds two points; name the tools at them "
                                              "with tools = [\"first\", \"second\"] in the body's table",
                                              b.name, file.string())
                                : fmt::format("body '{}' names two tools, and its space ({}) holds one point (build a "
                                              "two-point space: second_point in [precompute])",
                                              b.name, file.string()));
  if (levels.size() > 1) {
    try {
      if (two_points)
        return std::make_shared<CspaceBody>(
            index, precompute::PairInterpolator(std::move(levels), b.cspace->interpolation),
            std::array<std::size_t, 2>{b.cspace->tools[0], b.cspace->tools[1]});
      return std::make_shared<CspaceBody>(index, std::move(levels), b.cspace->interpolation);
    } catch (const InputError& e) {
      throw InputError(SourceLocation{file.string(), {}, {}, {}}, e.reason());
    }
  }
  return std::make_shared<CspaceBody>(index, std::move(levels.front()), b.cspace->interpolation);
}

CspaceBody::CspaceBody(std::size_t body, std::shared_ptr<const precompute::Space> space,
                       precompute::Interpolation method)
    : body_(body), interpolator_(std::in_place, std::move(space), method) {}

CspaceBody::CspaceBody(std::size_t body, std::vector<std::shared_ptr<const precompute::Space>> levels,
                       precompute::Interpolation method)
    : body_(body), probe_(std::in_place, std::move(levels), method) {}

CspaceBody::CspaceBody(std::size_t body, std::unique_ptr<precompute::OnlineBuilder> online, VecX rest)
    : body_(body), online_(std::move(online)), rest_(std::move(rest)) {}

CspaceBody::CspaceBody(std::size_t body, precompute::PairInterpolator pair, std::array<std::size_t, 2> tools)
    : body_(body), pair_(std::move(pair)), pair_tools_(tools) {}

CspaceBody::~CspaceBody() {
  if (online_) online_->stop();
}

void CspaceBody::count_box(bool in_box, double t) const noexcept {
  (in_box ? inside_ : outside_).fetch_add(1, std::memory_order_relaxed);
  if (in_box && first_inside_.load(std::memory_order_relaxed) < 0.0) first_inside_.store(t, std::memory_order_relaxed);
}

CspaceForce CspaceBody::force_on(int finger, const Vec3& p, const Quat& orientation, const Vec3* other,
                                 double t) const noexcept {
  if (!pair_) return force(p, orientation, t);
  CspaceForce out;
  const bool in_box = pair_->in_box(finger, p);
  count_box(in_box, t);
  if (!in_box) return out;
  const precompute::Query q = pair_->force(finger, p, other);
  if (q.valid && !q.outside && q.force.allFinite()) {
    out.force = q.force;
    out.touching = true;
  }
  return out;
}

CspaceForce CspaceBody::force(const Vec3& p, const Quat& orientation, double t) const noexcept {
  if (pair_) return force_on(0, p, orientation, nullptr, t);
  CspaceForce out;
  const precompute::Grid& g = online_ ? online_->grid()
                              : probe_ ? probe_->level(0).space().grid
                                       : interpolator_->space().grid;
  const Vec3 far = g.origin + g.spacing * Vec3(g.counts[0] - 1, g.counts[1] - 1, g.counts[2] - 1);
  const bool in_box = (p.array() >= g.origin.array()).all() && (p.array() <= far.array()).all();
  count_box(in_box, t);
  if (online_) {
    online_->observe(p, t);
    const precompute::OnlineQuery q = online_->render(p);
    const bool inside = in_box;
    // Attached once a point is solved; before that the render is zero. The render changes
    // by at most max_force_step per call, also when a cell completes.
    if (inside && q.force.allFinite()) {
      out.force = q.force;
      out.touching = online_->solved_count() > 0;
    }
    if (inside) {
      queries_.fetch_add(1, std::memory_order_relaxed);
      if (q.complete) complete_.fetch_add(1, std::memory_order_relaxed);
    }
    return out;
  }
  // A probe space renders the torque on the probe as well; a point space's patch has one too,
  // but the tool there is a point.
  const precompute::Query q =
      probe_ ? probe_->force_and_torque(p, probe_direction(orientation)) : interpolator_->force(p);
  if (q.valid && !q.outside && q.force.allFinite() && q.torque.allFinite()) {
    out.force = q.force;
    out.torque = q.torque;
    out.touching = true;
  }
  return out;
}

CspaceBody::BoxCounts CspaceBody::box_counts() const {
  return {inside_.load(std::memory_order_relaxed), outside_.load(std::memory_order_relaxed),
          first_inside_.load(std::memory_order_relaxed)};
}

void CspaceBody::positions(const Vec3* first, const Vec3* second, VecX& x) const {
  if (!pair_) {
    if (first) positions(*first, Quat::Identity(), x);
    return;
  }
  const std::array<const Vec3*, 2> at{first, second};
  precompute::Query q;
  for (int finger = 0; finger < 2 && !q.valid; ++finger)
    if (const Vec3* p = at[static_cast<std::size_t>(finger)]; p && pair_->in_box(finger, *p))
      q = pair_->shape(finger, *p, at[static_cast<std::size_t>(1 - finger)], x);
  const VecX& rest = pair_->level(0).space().rest_positions;
  if (!q.valid || x.size() != rest.size() || !x.allFinite()) x.setZero(rest.size());
  x += rest;
}

void CspaceBody::positions(const Vec3& p, const Quat& orientation, VecX& x) const {
  if (pair_) {
    positions(&p, nullptr, x);
    return;
  }
  if (online_) {
    if (!online_->shape(p, x) || !x.allFinite()) x.setZero(rest_.size());
    x += rest_;
    return;
  }
  const precompute::Query q =
      probe_ ? probe_->shape(p, probe_direction(orientation), x) : interpolator_->shape(p, x);
  if (!q.valid || !x.allFinite()) x.setZero();
  x += (probe_ ? probe_->level(0) : *interpolator_).space().rest_positions;
}

CspaceBody::OnlineCounts CspaceBody::online_counts() const {
  OnlineCounts n;
  n.solved = solved_points();
  n.points = online_  ? online_->grid().size()
             : probe_ ? probe_->level_count() * probe_->level(0).space().grid.size()
             : pair_  ? 0
                      : interpolator_->space().grid.size();
  if (pair_)
    for (std::size_t k = 0; k < pair_->level_count(); ++k) n.points += pair_->level(k).space().grid.size();
  n.queries = queries_.load(std::memory_order_relaxed);
  n.complete = complete_.load(std::memory_order_relaxed);
  return n;
}

std::size_t CspaceBody::solved_points() const {
  if (online_) return online_->solved_count();
  if (probe_ || pair_) {
    std::size_t n = 0;
    const std::size_t count = probe_ ? probe_->level_count() : pair_->level_count();
    for (std::size_t k = 0; k < count; ++k)
      n += (probe_ ? probe_->level(k) : pair_->level(k)).space().count(precompute::PointStatus::solved);
    return n;
  }
  return interpolator_->space().count(precompute::PointStatus::solved);
}

CspaceBodies load_cspace_bodies(const scene::Model& model) {
  CspaceBodies out(model.bodies.size());
  for (std::size_t i = 0; i < model.bodies.size(); ++i)
    if (model.bodies[i].cspace) out[i] = CspaceBody::load(model, i);
  return out;
}

std::shared_ptr<const CspaceBody> cspace_body(const scene::Model& model, std::size_t index, const CspaceBodies& bodies) {
  if (index < bodies.size() && bodies[index]) return bodies[index];
  return CspaceBody::load(model, index);
}

}  // namespace tactus::compile
