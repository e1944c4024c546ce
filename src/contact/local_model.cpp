#include "contact/local_model.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>

#include "contact/closest_point.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

constexpr double kMaxExtrapolation = 0.1;  // [s]: past this the watchdog fades the force anyway

Eigen::Index dof(int node) { return 3 * static_cast<Eigen::Index>(node); }

}  // namespace

const char* local_model_name(LocalModelKind kind) {
  switch (kind) {
    case LocalModelKind::plane: return "plane";
    case LocalModelKind::compliance: return "compliance";
    case LocalModelKind::mass_spring: return "mass_spring";
  }
  return "?";
}

LocalPatch::LocalPatch(LocalModelKind k, const PatchCapacity& c) : kind(k) {
  const auto nodes = static_cast<std::size_t>(c.nodes);
  const Eigen::Index free_dofs = 3 * static_cast<Eigen::Index>(c.free_nodes);
  position.assign(nodes, Vec3::Zero());
  velocity.assign(nodes, Vec3::Zero());
  triangles.assign(static_cast<std::size_t>(c.triangles), mesh::Triangle{0, 0, 0});
  surface_triangle.assign(static_cast<std::size_t>(c.triangles), -1);
  area.assign(nodes, 0.0);
  release = VecX::Zero(free_dofs);
  applied = VecX::Zero(free_dofs);
  response = Eigen::MatrixXf::Zero(free_dofs, free_dofs);
  // The mass-spring arrays only where they are used: a compliance patch carries less.
  const Eigen::Index ms = k == LocalModelKind::mass_spring ? free_dofs : 0;
  mass = VecX::Zero(ms);
  border_drift = VecX::Zero(ms);
}

// --- Patch sizing --------------------------------------------------------------------------

PatchSizing size_patch(std::span<const Vec3> vertices, std::span<const mesh::Triangle> triangles, double radius,
                       int max_free_nodes) {
  PatchSizing out;
  if (vertices.empty() || triangles.empty() || !(radius > 0.0)) return out;
  double edge = 0.0;
  for (const mesh::Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
      const auto b = static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)]);
      if (a < vertices.size() && b < vertices.size()) edge = std::max(edge, (vertices[a] - vertices[b]).norm());
    }
  // Every vertex within the radius is free (the builder keeps the nearest): then every
  // triangle with a corner inside has a free corner and is in the patch. The centre lies
  // anywhere, not on a vertex: half an edge more. Border nodes: one ring more.
  const double free_reach = radius + 0.5 * edge;
  const double node_reach = free_reach + edge;
  // Vertices binned in cubes of node_reach: each count looks at the 27 cubes around.
  const double cell = node_reach;
  auto key = [cell](const Vec3& p) {
    return std::array<long, 3>{static_cast<long>(std::floor(p.x() / cell)), static_cast<long>(std::floor(p.y() / cell)),
                               static_cast<long>(std::floor(p.z() / cell))};
  };
  std::map<std::array<long, 3>, std::vector<std::int32_t>> bins;
  for (std::size_t v = 0; v < vertices.size(); ++v) bins[key(vertices[v])].push_back(static_cast<std::int32_t>(v));
  int most_free = 0, most_nodes = 0;
  for (const Vec3& centre : vertices) {
    const std::array<long, 3> c = key(centre);
    int free = 0, nodes = 0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = bins.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == bins.end()) continue;
          for (const std::int32_t v : it->second) {
            const double d = (vertices[static_cast<std::size_t>(v)] - centre).norm();
            free += d <= free_reach ? 1 : 0;
            nodes += d <= node_reach ? 1 : 0;
          }
        }
    most_free = std::max(most_free, free);
    most_nodes = std::max(most_nodes, nodes);
  }
  out.needed_free_nodes = most_free;
  out.capped = most_free > max_free_nodes;
  // Never smaller than the default: a coarse mesh keeps the patch it always had.
  const PatchCapacity fallback;
  out.capacity.free_nodes = std::max(fallback.free_nodes, std::min(most_free, max_free_nodes));
  out.capacity.nodes = std::max({fallback.nodes, most_nodes, out.capacity.free_nodes + (most_nodes - most_free)});
  // A triangle mesh has about two triangles per vertex; a patch's rim adds one per node.
  out.capacity.triangles = std::max(fallback.triangles, 3 * out.capacity.nodes);
  return out;
}

// --- PatchBuilder (simulation thread) ------------------------------------------------------

PatchBuilder::PatchBuilder(std::size_t vertex_count, std::span<const mesh::Triangle> triangles,
                           PatchCapacity capacity)
    : vertex_count_(vertex_count), triangles_(triangles.begin(), triangles.end()),
      vertex_triangles_(vertex_count), capacity_(capacity), local_of_(vertex_count, -1) {
  if (capacity.free_nodes <= 0 || capacity.nodes < capacity.free_nodes || capacity.triangles <= 0)
    throw InputError(fmt::format("local model: capacity of {} free nodes, {} nodes and {} triangles is not usable",
                                 capacity.free_nodes, capacity.nodes, capacity.triangles));
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (const mesh::Index v : triangles_[t]) {
      if (v < 0 || static_cast<std::size_t>(v) >= vertex_count)
        throw InputError(fmt::format("local model: triangle {} refers to vertex {}, but there are {} vertices", t, v,
                                     vertex_count));
      vertex_triangles_[static_cast<std::size_t>(v)].push_back(static_cast<std::int32_t>(t));
    }
}

void PatchBuilder::select(const Inputs& in, LocalPatch& out) {
  for (const std::int32_t v : patch_vertex_) local_of_[static_cast<std::size_t>(v)] = -1;
  patch_vertex_.clear();
  // Free: the corners of every triangle the sphere touches (a coarse mesh may have no vertex
  // inside the sphere at all), nearest first while the capacity lasts.
  candidates_.clear();
  const double r2 = in.radius * in.radius;
  for (const mesh::Triangle& tri : triangles_) {
    const Vec3& a = in.surface[static_cast<std::size_t>(tri[0])];
    const Vec3& b = in.surface[static_cast<std::size_t>(tri[1])];
    const Vec3& c = in.surface[static_cast<std::size_t>(tri[2])];
    if ((closest_point_on_triangle(in.center, a, b, c).point - in.center).squaredNorm() > r2) continue;
    for (const mesh::Index v : tri) {
      if (local_of_[static_cast<std::size_t>(v)] == -2) continue;
      local_of_[static_cast<std::size_t>(v)] = -2;  // a candidate already
      candidates_.emplace_back((in.surface[static_cast<std::size_t>(v)] - in.center).squaredNorm(), v);
    }
  }
  for (const auto& c : candidates_) local_of_[static_cast<std::size_t>(c.second)] = -1;
  std::sort(candidates_.begin(), candidates_.end());
  if (candidates_.size() > static_cast<std::size_t>(capacity_.free_nodes))
    candidates_.resize(static_cast<std::size_t>(capacity_.free_nodes));

  auto add_node = [&](std::int32_t v) {
    local_of_[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(patch_vertex_.size());
    patch_vertex_.push_back(v);
  };
  for (const auto& c : candidates_) add_node(c.second);  // free nodes first, nearest first
  out.free_count = static_cast<int>(patch_vertex_.size());

  // Every triangle with a free corner, while the capacity lasts; its other corners are border.
  int tri_count = 0;
  for (int f = 0; f < out.free_count; ++f) {
    for (const std::int32_t t : vertex_triangles_[static_cast<std::size_t>(patch_vertex_[static_cast<std::size_t>(f)])]) {
      const mesh::Triangle& tri = triangles_[static_cast<std::size_t>(t)];
      // Taken already when a free corner with a lower index took it.
      bool taken = false;
      for (const mesh::Index v : tri) {
        const std::int32_t l = local_of_[static_cast<std::size_t>(v)];
        if (l >= 0 && l < f) taken = true;
      }
      if (taken) continue;
      int new_nodes = 0;
      for (const mesh::Index v : tri) new_nodes += local_of_[static_cast<std::size_t>(v)] < 0 ? 1 : 0;
      if (tri_count >= capacity_.triangles || static_cast<int>(patch_vertex_.size()) + new_nodes > capacity_.nodes)
        continue;
      mesh::Triangle local{};
      for (int k = 0; k < 3; ++k) {
        const mesh::Index v = tri[static_cast<std::size_t>(k)];
        if (local_of_[static_cast<std::size_t>(v)] < 0) add_node(v);
        local[static_cast<std::size_t>(k)] = local_of_[static_cast<std::size_t>(v)];
      }
      out.triangles[static_cast<std::size_t>(tri_count)] = local;
      out.surface_triangle[static_cast<std::size_t>(tri_count)] = t;
      ++tri_count;
    }
  }
  out.triangle_count = tri_count;
  out.node_count = static_cast<int>(patch_vertex_.size());

  const bool moving = in.surface_previous.size() == in.surface.size() && in.step_period > 0.0;
  const bool with_areas = in.vertex_area.size() == in.surface.size();
  for (int n = 0; n < out.node_count; ++n) {
    const auto v = static_cast<std::size_t>(patch_vertex_[static_cast<std::size_t>(n)]);
    out.position[static_cast<std::size_t>(n)] = in.surface[v];
    out.area[static_cast<std::size_t>(n)] = with_areas ? in.vertex_area[v] : 1.0;
    out.velocity[static_cast<std::size_t>(n)] =
        moving ? Vec3((in.surface[v] - in.surface_previous[v]) / in.step_period) : Vec3::Zero();
  }

  // The contact load of the step on the free nodes: the shape already carries it.
  out.applied.setZero();
  for (const LoadShare& s : in.load_shares) {
    if (s.vertex < 0 || static_cast<std::size_t>(s.vertex) >= vertex_count_) continue;
    const std::int32_t l = local_of_[static_cast<std::size_t>(s.vertex)];
    if (l >= 0 && l < out.free_count) out.applied.segment<3>(dof(l)) += s.share * in.load_force;
  }
}

void PatchBuilder::hold_still(LocalPatch& out) {
  const Eigen::Index f3 = dof(out.free_count);
  out.response.topLeftCorner(f3, f3).setZero();
  out.release.head(f3).setZero();
  if (out.border_drift.size() >= f3) out.border_drift.head(f3).setZero();  // where this kind has it
}

void PatchBuilder::condense_compliance(const Inputs& in, LocalPatch& out) {
  if (!in.physics_body || !in.physics_state) {  // no body to condense: it does not yield
    hold_still(out);
    return;
  }
  if (in.surface_to_node.size() != vertex_count_)
    throw std::runtime_error("local model: the compliance model needs the body's surface-to-node map");
  const physics::Body& body = *in.physics_body;
  const physics::BodyState& state = *in.physics_state;
  const physics::ForceModel& model = *body.model;
  if (!scratch_) scratch_ = model.make_scratch();
  model.linearize(state.x, state.v, state.q, *scratch_);
  triplets_.clear();
  model.add_triplets(1.0, 0.0, triplets_, *scratch_);
  const VecX& m = model.lumped_mass();
  const auto n = static_cast<Eigen::Index>(m.size());
  auto fixed = [&](Eigen::Index i) {
    return static_cast<std::size_t>(i) < body.fixed_dofs.size() && body.fixed_dofs[static_cast<std::size_t>(i)] != 0;
  };
  // Fixed dofs drop out (identity rows). The inertia over one step period is kept (M/T²): it
  // is the tissue's resistance over the time the patch lives, and keeps a body that is not
  // held anywhere solvable.
  std::size_t keep = 0;
  for (const auto& t : triplets_)
    if (!fixed(t.row()) && !fixed(t.col())) triplets_[keep++] = t;
  triplets_.resize(keep);
  const double inertia = in.step_period > 0.0 ? 1.0 / (in.step_period * in.step_period) : 0.0;
  for (Eigen::Index i = 0; i < n; ++i) triplets_.emplace_back(i, i, fixed(i) ? 1.0 : inertia * m[i]);
  stiffness_.resize(n, n);
  stiffness_.setFromTriplets(triplets_.begin(), triplets_.end());
  if (!pattern_analyzed_) {
    solver_.analyzePattern(stiffness_);
    pattern_analyzed_ = true;
  }
  solver_.factorize(stiffness_);
  if (solver_.info() != Eigen::Success)
    throw std::runtime_error("local model: the condensed stiffness is not positive definite");

  const int free = out.free_count;
  const Eigen::Index f3 = dof(free);
  response_.setZero(f3, f3);
  unit_.setZero(n);
  for (int j = 0; j < free; ++j) {
    const auto node_j = static_cast<Eigen::Index>(in.surface_to_node[static_cast<std::size_t>(patch_vertex_[static_cast<std::size_t>(j)])]);
    for (int a = 0; a < 3; ++a) {
      const Eigen::Index col = dof(j) + a;
      if (fixed(3 * node_j + a)) continue;
      unit_[3 * node_j + a] = 1.0;
      solution_ = solver_.solve(unit_);
      unit_[3 * node_j + a] = 0.0;
      for (int i = 0; i < free; ++i) {
        const auto node_i = static_cast<Eigen::Index>(in.surface_to_node[static_cast<std::size_t>(patch_vertex_[static_cast<std::size_t>(i)])]);
        for (int b = 0; b < 3; ++b) response_(dof(i) + b, col) = fixed(3 * node_i + b) ? 0.0 : solution_[3 * node_i + b];
      }
    }
  }
  out.release.head(f3).noalias() = -response_ * out.applied.head(f3);
  store_response(out);
}

void PatchBuilder::store_response(LocalPatch& out) const {
  const Eigen::Index f3 = response_.rows();
  // Symmetric by construction; average away the round-off so the response stays passive.
  out.response.topLeftCorner(f3, f3) = (0.5 * (response_ + response_.transpose())).cast<float>();
}

void PatchBuilder::fit_mass_spring(const Inputs& in, LocalPatch& out) {
  const PatchMaterial& mat = in.material;
  if (!(mat.young_modulus > 0.0) || !(mat.density > 0.0) || !(in.frame_time > 0.0))
    throw std::runtime_error("local model: the mass_spring model needs a material and a haptic period");
  const int nodes = out.node_count, free = out.free_count;
  const double shear = mat.young_modulus / (2.0 * (1.0 + mat.poisson_ratio));
  const double plane_strain = mat.young_modulus / (1.0 - mat.poisson_ratio * mat.poisson_ratio);
  full_.setZero(dof(nodes), dof(nodes));
  area_.assign(static_cast<std::size_t>(nodes), 0.0);
  // An edge spring as stiff as a shear block of its own length, G·L; each triangle gives half
  // of it (an inner edge has two triangles).
  auto add_half_spring = [&](int i, int j) {
    const Vec3 e = out.position[static_cast<std::size_t>(j)] - out.position[static_cast<std::size_t>(i)];
    const double length = e.norm();
    if (!(length > 0.0)) return;
    const Mat3 block = 0.5 * shear * length * (e / length) * (e / length).transpose();
    full_.block<3, 3>(dof(i), dof(i)) += block;
    full_.block<3, 3>(dof(j), dof(j)) += block;
    full_.block<3, 3>(dof(i), dof(j)) -= block;
    full_.block<3, 3>(dof(j), dof(i)) -= block;
  };
  for (int t = 0; t < out.triangle_count; ++t) {
    const mesh::Triangle& tri = out.triangles[static_cast<std::size_t>(t)];
    const Vec3& a = out.position[static_cast<std::size_t>(tri[0])];
    const Vec3& b = out.position[static_cast<std::size_t>(tri[1])];
    const Vec3& c = out.position[static_cast<std::size_t>(tri[2])];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    for (const mesh::Index v : tri) area_[static_cast<std::size_t>(v)] += area / 3.0;
    for (int k = 0; k < 3; ++k) {
      const int i = tri[static_cast<std::size_t>(k)], j = tri[static_cast<std::size_t>((k + 1) % 3)];
      if (i < free || j < free) add_half_spring(i, j);  // springs between border nodes do nothing
    }
  }
  // The tissue under each free node: the Boussinesq stiffness of a rigid punch as large as
  // the node's share of the surface, 2a·E/(1 − ν²); its mass a column as deep as it is wide.
  // On a coarse FEM block this is softer than the body, and a patch softer than the body
  // does net work on the hand at updates (docs/contact-mechanics.md, "Local models").
  for (int i = 0; i < free; ++i) {
    const double area = area_[static_cast<std::size_t>(i)];
    const double a = std::sqrt(area / std::numbers::pi);
    full_.block<3, 3>(dof(i), dof(i)) += 2.0 * a * plane_strain * Mat3::Identity();
    out.mass.segment<3>(dof(i)).setConstant(mat.density * area * std::sqrt(area));
  }
  finish_mass_spring(in, out);
}

void PatchBuilder::take_body_stiffness(const Inputs& in, LocalPatch& out) {
  if (!in.physics_body || !in.physics_state || in.surface_to_node.size() != vertex_count_)
    throw std::runtime_error("local model: a patch of the body's own stiffness needs the body, its state and its node map");
  const physics::Body& body = *in.physics_body;
  const physics::BodyState& state = *in.physics_state;
  const physics::ForceModel& model = *body.model;
  if (!scratch_) scratch_ = model.make_scratch();
  model.linearize(state.x, state.v, state.q, *scratch_);
  const physics::BlockMatrix* k = model.assemble_system(0.0, 0.0, 1.0, *scratch_);
  if (!k) throw std::runtime_error("local model: the body assembles no stiffness; use local_model = \"compliance\"");
  const int nodes = out.node_count, free = out.free_count;
  node_patch_.assign(model.node_count(), -1);
  auto body_node = [&](int p) {
    return static_cast<std::size_t>(in.surface_to_node[static_cast<std::size_t>(patch_vertex_[static_cast<std::size_t>(p)])]);
  };
  for (int p = 0; p < nodes; ++p) node_patch_[body_node(p)] = p;
  full_.setZero(dof(nodes), dof(nodes));
  const VecX& m = model.lumped_mass();
  for (int p = 0; p < nodes; ++p) {
    const std::size_t i = body_node(p);
    full_.block<3, 3>(dof(p), dof(p)) = k->diagonal[i];
    for (auto b = k->row_start[i]; b < k->row_start[i + 1]; ++b) {
      const int q = node_patch_[static_cast<std::size_t>(k->column[static_cast<std::size_t>(b)])];
      if (q < 0) continue;
      full_.block<3, 3>(dof(p), dof(q)) = k->upper[static_cast<std::size_t>(b)];
      full_.block<3, 3>(dof(q), dof(p)) = k->upper[static_cast<std::size_t>(b)].transpose();
    }
    if (p < free) out.mass.segment<3>(dof(p)) = m.segment<3>(3 * static_cast<Eigen::Index>(i));
  }
  // A held node (the stand's clamp) inside the patch stays where it is: no stiffness, and a
  // mass that nothing in a frame can move.
  for (int p = 0; p < free; ++p)
    for (int a = 0; a < 3; ++a) {
      const std::size_t d = 3 * body_node(p) + static_cast<std::size_t>(a);
      if (d < body.fixed_dofs.size() && body.fixed_dofs[d]) {
        full_.row(dof(p) + a).setZero();
        full_.col(dof(p) + a).setZero();
        out.mass[dof(p) + a] = 1e12 * m[static_cast<Eigen::Index>(d)];
      }
    }
  for (int p = 0; p < nodes; ++p) node_patch_[body_node(p)] = -1;
  finish_mass_spring(in, out);
}

void PatchBuilder::finish_mass_spring(const Inputs& in, LocalPatch& out) {
  const int nodes = out.node_count, free = out.free_count;
  const Eigen::Index f3 = dof(free);
  const double h = in.frame_time;
  // Border at constant velocity: force on the free nodes per second of it, K_FB·v_B.
  border_velocity_.setZero(dof(nodes) - f3);
  for (int n = free; n < nodes; ++n) border_velocity_.segment<3>(dof(n) - f3) = out.velocity[static_cast<std::size_t>(n)];
  out.border_drift.head(f3).noalias() = full_.topRightCorner(f3, dof(nodes) - f3) * border_velocity_;
  // Implicit Euler: (M/h + h·K_FF) v' = M v/h − K_FF u − K_FB (x_B' − p_B) + f.
  system_ = h * full_.topLeftCorner(f3, f3);
  system_.diagonal() += out.mass.head(f3) / h;
  const Eigen::LLT<MatX> llt(system_);
  if (llt.info() != Eigen::Success) throw std::runtime_error("local model: the mass-spring system is not positive definite");
  response_ = h * llt.solve(MatX::Identity(f3, f3));
  store_response(out);
  out.release.head(f3).setZero();
}

void PatchBuilder::build(const Inputs& in, LocalPatch& out) {
  out.kind = in.kind;
  out.body = in.body;
  out.time = in.time;
  out.center = in.center;
  out.radius = in.radius;
  out.valid = false;
  if (in.surface.size() != vertex_count_) {
    out.free_count = out.node_count = out.triangle_count = 0;
    return;
  }
  select(in, out);
  if (out.free_count == 0 || out.triangle_count == 0) {
    out.free_count = out.node_count = out.triangle_count = 0;
    return;
  }
  out.frame_time = in.frame_time;
  if (in.rigid) hold_still(out);  // whatever the kind: a rigid body does not yield
  else if (in.kind == LocalModelKind::compliance) condense_compliance(in, out);
  else if (in.kind == LocalModelKind::mass_spring && in.own_stiffness) take_body_stiffness(in, out);
  else if (in.kind == LocalModelKind::mass_spring) fit_mass_spring(in, out);
  out.valid = true;
}

// --- LocalModel (haptic thread) ------------------------------------------------------------

LocalModel::LocalModel(LocalModelKind kind, const PatchCapacity& capacity)
    : none_(kind, capacity), current_(static_cast<std::size_t>(capacity.nodes), Vec3::Zero()) {
  const Eigen::Index f3 = 3 * static_cast<Eigen::Index>(capacity.free_nodes);
  u_ = VecX::Zero(f3);
  v_ = VecX::Zero(f3);
  rhs_ = VecX::Zero(f3);
  next_ = VecX::Zero(f3);
  columns_ = MatX::Zero(f3, kMaxContacts);
  shares_.resize(static_cast<std::size_t>(capacity.nodes));
}

void LocalModel::reset(const LocalPatch& patch, double now) {
  if (patch.position.size() != none_.position.size() || patch.response.rows() != none_.response.rows() ||
      patch.mass.size() != none_.mass.size())
    throw std::invalid_argument("local model: a patch of another capacity or kind");
  patch_ = &patch;
  u_.setZero();
  v_.setZero();
  now_ = now;
  since_ = std::clamp(now - patch_->time, 0.0, kMaxExtrapolation);
  query_ = BruteForceSurfaceQuery(positions(), {patch_->triangles.data(), static_cast<std::size_t>(patch_->triangle_count)});
  place_nodes();
}

void LocalModel::extrapolate(double now) {
  now_ = now;
  since_ = std::clamp(now - patch_->time, 0.0, kMaxExtrapolation);
  place_nodes();
}

void LocalModel::place_nodes() {
  const bool drift = patch_->kind == LocalModelKind::mass_spring;
  for (int n = 0; n < patch_->node_count; ++n) {
    const auto i = static_cast<std::size_t>(n);
    if (n < patch_->free_count) current_[i] = patch_->position[i] + u_.segment<3>(dof(n));
    else current_[i] = drift ? Vec3(patch_->position[i] + since_ * patch_->velocity[i]) : patch_->position[i];
  }
}

Vec3 LocalModel::moved_since_published(std::int32_t triangle, const Vec3& barycentric) const {
  Vec3 moved = Vec3::Zero();
  if (!patch_->valid || triangle < 0 || triangle >= patch_->triangle_count) return moved;
  const mesh::Triangle& corners = patch_->triangles[static_cast<std::size_t>(triangle)];
  for (int k = 0; k < 3; ++k) {
    const auto v = static_cast<std::size_t>(corners[static_cast<std::size_t>(k)]);
    moved += barycentric[k] * (current_[v] - patch_->position[v]);
  }
  return moved;
}

Vec3 LocalModel::point_of(std::span<const Vec3> vertices, std::int32_t triangle, const Vec3& barycentric) const {
  if (!patch_->valid || triangle < 0 || triangle >= patch_->triangle_count)
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  return mesh::point_on(vertices, patch_->triangles[static_cast<std::size_t>(triangle)], barycentric);
}

Vec3 LocalModel::point(std::int32_t triangle, const Vec3& barycentric) const {
  return point_of(positions(), triangle, barycentric);
}

Vec3 LocalModel::published_point(std::int32_t triangle, const Vec3& barycentric) const {
  return point_of(patch_->position, triangle, barycentric);
}

double LocalModel::advance(const PatchContact& contact, double dt) {
  double settled = 0.0;
  advance(std::span<const PatchContact>(&contact, 1), dt, std::span<double>(&settled, 1));
  return patch_->valid ? settled : contact.force;
}

void LocalModel::advance(std::span<const PatchContact> contacts, double dt, std::span<double> settled) {
  for (double& f : settled) f = 0.0;
  contact_motion_.setZero();
  if (!patch_->valid) return;
  const int free = patch_->free_count;
  const Eigen::Index f3 = dof(free);
  auto a = next_.head(f3);
  if (patch_->kind == LocalModelKind::mass_spring) {
    // The response was built for the patch's frame time; a frame of another length (a late
    // frame in real time) advances by that frame time all the same.
    // Implicit Euler, A·v' = M·v/h − K_FF·u − K_FB·(x_B' − p_B) + f with A = M/h + h·K_FF and
    // u' = u + h·v'. Since h·A⁻¹·K_FF = I − A⁻¹·M/h, the stiffness drops out:
    // u' = h·A⁻¹·(M·(u/h + v)/h − f_applied − (since + h)·K_FB·v_B), one product with the
    // response. (The contact force enters below through the same response.)
    (void)dt;
    const double h = patch_->frame_time;
    rhs_.head(f3) = patch_->mass.head(f3).cwiseProduct(u_.head(f3) / h + v_.head(f3)) / h -
                    patch_->applied.head(f3) - (since_ + h) * patch_->border_drift.head(f3);
    a.setZero();
    for (Eigen::Index j = 0; j < f3; ++j) a += rhs_[j] * patch_->response.col(j).head(f3).cast<double>();
  } else {
    a = patch_->release.head(f3);
  }

  // The contacts on the patch, at most kMaxContacts (index into `contacts` of each).
  std::array<int, kMaxContacts> which{};
  int n = 0;
  for (std::size_t i = 0; i < contacts.size() && n < kMaxContacts; ++i)
    if (contacts[i].triangle >= 0 && contacts[i].triangle < patch_->triangle_count) which[static_cast<std::size_t>(n++)] = static_cast<int>(i);

  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxContacts, kMaxContacts>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxContacts, 1>;
  Small coupling(n, n);  // C_ij: contact i's point moves C_ij·F_j along its normal under F_j
  SmallVec free_motion(n), stiffness(n), law(n);
  for (int i = 0; i < n; ++i) {
    const PatchContact& c = contacts[static_cast<std::size_t>(which[static_cast<std::size_t>(i)])];
    // The force acts on the nodes around the contact point as the simulation spreads it
    // (load_spread.hpp), so that the patch dents as the body will.
    const int count = spread_load(positions(),
                                  {patch_->triangles.data(), static_cast<std::size_t>(patch_->triangle_count)},
                                  {patch_->area.data(), static_cast<std::size_t>(patch_->node_count)}, c.triangle,
                                  c.barycentric, c.contact_radius, shares_);
    // column = B·g, g = Σ share·n over the free nodes: their response to a unit normal force.
    auto column = columns_.col(i).head(f3);
    column.setZero();
    for (int j = 0; j < count; ++j) {
      const LoadShare& sh = shares_[static_cast<std::size_t>(j)];
      if (sh.vertex >= free) continue;
      const Vec3 g = sh.share * c.normal;
      for (int k = 0; k < 3; ++k) column += g[k] * patch_->response.col(dof(sh.vertex) + k).head(f3).cast<double>();
    }
    stiffness[i] = std::max(0.0, c.stiffness);
    law[i] = c.force;
  }
  for (int i = 0; i < n; ++i) {
    // The contact point is the material point at `barycentric` on the contact triangle: its
    // motion is what the contact law sees, however widely the load is spread, and a proxy
    // resting there rides with it.
    const PatchContact& c = contacts[static_cast<std::size_t>(which[static_cast<std::size_t>(i)])];
    const mesh::Triangle& corners = patch_->triangles[static_cast<std::size_t>(c.triangle)];
    double s_a = 0.0, s = 0.0;
    for (int j = 0; j < n; ++j) coupling(i, j) = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int v = corners[static_cast<std::size_t>(k)];
      if (v >= free) continue;  // a border corner does not move under the contact
      const double w = c.barycentric[k];
      for (int j = 0; j < n; ++j) coupling(i, j) += w * c.normal.dot(columns_.col(j).segment<3>(dof(v)));
      s_a += w * c.normal.dot(a.segment<3>(dof(v)));
      s += w * c.normal.dot(u_.segment<3>(dof(v)));
    }
    coupling(i, i) = std::max(0.0, coupling(i, i));
    free_motion[i] = s_a - s;
  }
  // Each contact point moves (s_a − s) − Σ_j C_ij·F_j along its normal; its law answers with
  // F_i = F0_i + k_i·(that), linearized: (I + K·C)·F = F0 + K·(s_a − s), solved exactly.
  // Forces only push: a contact that would pull is released and the rest solved again.
  SmallVec force = SmallVec::Zero(n);
  std::array<bool, kMaxContacts> active{};
  for (int i = 0; i < n; ++i) active[static_cast<std::size_t>(i)] = true;
  for (int round = 0; round < n; ++round) {
    Small system = Small::Identity(n, n);
    SmallVec rhs(n);
    for (int i = 0; i < n; ++i) {
      if (!active[static_cast<std::size_t>(i)]) {
        rhs[i] = 0.0;  // F_i = 0
        continue;
      }
      for (int j = 0; j < n; ++j)
        if (active[static_cast<std::size_t>(j)]) system(i, j) += stiffness[i] * coupling(i, j);
      rhs[i] = law[i] + stiffness[i] * free_motion[i];
    }
    force = n == 1 ? SmallVec::Constant(1, rhs[0] / system(0, 0)) : SmallVec(system.partialPivLu().solve(rhs));
    int most_negative = -1;
    for (int i = 0; i < n; ++i)
      if (active[static_cast<std::size_t>(i)] && force[i] < 0.0 && (most_negative < 0 || force[i] < force[most_negative]))
        most_negative = i;
    if (most_negative < 0) break;
    active[static_cast<std::size_t>(most_negative)] = false;
  }
  for (int i = 0; i < n; ++i) {
    double& f = force[i];
    if (!active[static_cast<std::size_t>(i)] || !std::isfinite(f) || f < 0.0) f = 0.0;
    a.noalias() -= f * columns_.col(i).head(f3);
    const auto slot = static_cast<std::size_t>(which[static_cast<std::size_t>(i)]);
    if (slot < settled.size()) settled[slot] = f;
  }
  if (n > 0) {
    // The first contact's motion: the one a proxy resting on the patch rides with.
    const PatchContact& c = contacts[static_cast<std::size_t>(which[0])];
    const mesh::Triangle& corners = patch_->triangles[static_cast<std::size_t>(c.triangle)];
    for (int k = 0; k < 3; ++k) {
      const int v = corners[static_cast<std::size_t>(k)];
      if (v < free) contact_motion_ += c.barycentric[k] * (a.segment<3>(dof(v)) - u_.segment<3>(dof(v)));
    }
  }
  if (patch_->kind == LocalModelKind::mass_spring) v_.head(f3) = (a - u_.head(f3)) / patch_->frame_time;
  u_.head(f3) = a;
  place_nodes();
}

}  // namespace tactus::contact
