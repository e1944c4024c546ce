#pragma once
// Local contact models for the haptic rate (seed 002 §IV, DESIGN "The loops"): the simulation
// publishes, with each step, a small patch of the surface inside a bounding sphere around the
// tool, and between steps the haptic loop deforms that patch under the contact force so that
// the dent and the edges are felt at the haptic rate, not only a plane.
//
// The patch's nodes are split into free nodes (inside the sphere: they move under the
// contact) and border nodes (the other corners of the patch's triangles: they move at the
// constant velocity of the last two snapshots). Two dynamics for the free nodes:
//   - compliance: u = C·(f − f_applied), C the free nodes' compliance condensed from the
//     body's global stiffness at the last step (quasi-static, exact for a linear body);
//   - mass_spring: springs along the patch edges (rest lengths from the published shape,
//     stiffness from the material), a support spring per node standing in for the tissue
//     beneath, lumped masses, stepped at the haptic rate by implicit Euler.
// Both are linear in the contact force, so the haptic loop advances them with a matrix-vector
// product and solves the contact force implicitly with one scalar equation: stable for any
// contact stiffness, no factorization and no allocation per frame.
//
// PatchBuilder runs in the simulation thread (it allocates); LocalModel in the haptic thread
// (it never allocates after construction).
#include <Eigen/SparseCholesky>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "contact/load_spread.hpp"
#include "contact/local_model_kind.hpp"
#include "contact/surface_query.hpp"
#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"
#include "physics/body.hpp"

namespace tactus::contact {

/// How big a patch may grow; fixed when the channels are built, so no loop reallocates.
struct PatchCapacity {
  int free_nodes = 24;  ///< nodes that move under the contact (3·free_nodes rows of C)
  int nodes = 96;       ///< free plus border nodes
  int triangles = 160;
};

/// The capacity a patch of `radius` needs on this surface: the most vertices a sphere of
/// that radius can hold anywhere on the surface (and their triangles and border ring), so
/// that every triangle with a corner in the sphere is in the patch and the tool never
/// reaches the patch's rim between two simulation steps. Capped at
/// `max_free_nodes` (the haptic frame's cost grows with the square of the free nodes);
/// `capped` then says the surface is too fine for a patch of this radius.
struct PatchSizing {
  PatchCapacity capacity;
  int needed_free_nodes = 0;  ///< before the cap
  bool capped = false;
};
[[nodiscard]] PatchSizing size_patch(std::span<const Vec3> vertices, std::span<const mesh::Triangle> triangles,
                                     double radius, int max_free_nodes = 48);

/// Material of the tissue under the patch (mass_spring fits its springs to it).
struct PatchMaterial {
  double young_modulus = 0.0;  ///< [Pa]
  double poisson_ratio = 0.45;
  double density = 1000.0;     ///< [kg/m³]
};

/// One published local model. Every array is sized to the capacity once; the counts say how
/// much of it is in use, so copying one patch onto another never allocates.
struct LocalPatch {
  LocalPatch() = default;
  LocalPatch(LocalModelKind kind, const PatchCapacity& capacity);

  LocalModelKind kind = LocalModelKind::compliance;
  bool valid = false;        ///< false: no surface near the tool (render no contact)
  std::int32_t body = -1;    ///< index into Model::bodies
  double time = 0.0;         ///< simulation time of the shape [s]
  Vec3 center = Vec3::Zero();
  double radius = 0.0;       ///< of the bounding sphere [m]
  int free_count = 0;        ///< free nodes are the first free_count nodes
  int node_count = 0;
  int triangle_count = 0;

  std::vector<Vec3> position;  ///< published shape, per node [m]
  std::vector<Vec3> velocity;  ///< from the last two snapshots, per node [m/s]
  std::vector<mesh::Triangle> triangles;         ///< corners as patch node indices
  std::vector<std::int32_t> surface_triangle;    ///< the body's surface triangle of each
  std::vector<double> area;  ///< each node's share of the body's surface [m²] (spreads loads)
  /// Free-node displacement when the contact force is released to zero: −C·f_applied
  /// (compliance), where f_applied is the contact load the last step applied (3·free).
  VecX release;
  /// The contact load the last step applied to each free node (3·free) [N].
  VecX applied;
  /// Linear response of the free nodes to a change of nodal force over one haptic frame,
  /// 3F×3F, symmetric: C itself (compliance) or h·A⁻¹ with A = M/h + h·K_FF (mass_spring)
  /// [m/N]. It is the only matrix a frame reads (LocalModel::advance), fresh from the
  /// simulation thread at each update, so it is stored in single precision: half the memory
  /// traffic of that frame, and 7 digits are far finer than any device renders.
  Eigen::MatrixXf response;
  /// mass_spring only: lumped masses (3F) and the force on the free nodes per second of
  /// border motion, K_FB·v_B (3F).
  VecX mass;
  VecX border_drift;
  double frame_time = 0.0;  ///< h, the haptic period the mass_spring system was built for [s]
};

/// Builds patches of one body's surface. Construction allocates its buffers; build() may
/// allocate too (it runs in the simulation thread, never in the haptic loop).
class PatchBuilder {
 public:
  /// `triangles` is the body's surface; `capacity` the size of every patch it fills.
  /// Throws InputError when a triangle refers to a vertex that does not exist or the
  /// capacity is not positive.
  PatchBuilder(std::size_t vertex_count, std::span<const mesh::Triangle> triangles, PatchCapacity capacity);

  struct Inputs {
    LocalModelKind kind = LocalModelKind::compliance;
    std::int32_t body = -1;
    double time = 0.0;
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    std::span<const Vec3> surface;           ///< surface vertex positions now
    std::span<const Vec3> surface_previous;  ///< one step earlier (empty: at rest)
    double step_period = 0.0;                ///< time between the two [s]
    /// Each surface vertex's share of the body's surface [m²] (empty: equal shares).
    std::span<const double> vertex_area;
    /// Contact load the step applied: the surface vertices' shares of the force on the tissue.
    std::span<const LoadShare> load_shares;
    Vec3 load_force = Vec3::Zero();
    /// The body does not deform (a rigid body): the patch does not yield, whatever the kind.
    bool rigid = false;
    /// compliance: the body, its state after the step and its surface vertex → node map.
    const physics::Body* physics_body = nullptr;
    const physics::BodyState* physics_state = nullptr;
    std::span<const std::int32_t> surface_to_node;
    /// mass_spring: the material and the haptic period.
    PatchMaterial material;
    /// mass_spring on a body with nothing under it (a fabric): the springs are the body's own
    /// stiffness linearized at its state (the physics body and state above), no material.
    bool own_stiffness = false;
    double frame_time = 1e-3;
  };

  /// Fills `out` (made with this builder's capacity): the surface vertices within `radius`
  /// of `center`, nearest first up to the capacity, are the free nodes; every triangle with
  /// a free corner is in the patch. No vertex within the radius gives an invalid patch.
  /// Throws std::runtime_error when the condensed stiffness cannot be factorized.
  void build(const Inputs& in, LocalPatch& out);

 private:
  void select(const Inputs& in, LocalPatch& out);
  /// A patch that does not yield: zero response, nothing to release, no dynamics.
  static void hold_still(LocalPatch& out);
  void condense_compliance(const Inputs& in, LocalPatch& out);
  /// out.response from response_, made exactly symmetric and rounded to single precision.
  void store_response(LocalPatch& out) const;
  void fit_mass_spring(const Inputs& in, LocalPatch& out);
  /// The body's assembled stiffness restricted to the patch, its lumped masses (own_stiffness).
  void take_body_stiffness(const Inputs& in, LocalPatch& out);
  /// The mass_spring patch's dynamics from full_ and out.mass: border drift and response.
  void finish_mass_spring(const Inputs& in, LocalPatch& out);

  std::size_t vertex_count_;
  std::vector<mesh::Triangle> triangles_;
  std::vector<std::vector<std::int32_t>> vertex_triangles_;  ///< per vertex, its triangles
  PatchCapacity capacity_;
  std::vector<std::int32_t> local_of_;  ///< surface vertex → patch node (−1: not in the patch)
  std::vector<std::pair<double, std::int32_t>> candidates_;
  std::vector<std::int32_t> patch_vertex_;  ///< patch node → surface vertex
  // compliance: the body's stiffness and its factorization (pattern analyzed once)
  std::unique_ptr<physics::Scratch> scratch_;
  std::vector<physics::Triplet> triplets_;
  physics::SparseMatrix stiffness_;
  Eigen::SimplicialLDLT<physics::SparseMatrix> solver_;
  bool pattern_analyzed_ = false;
  VecX unit_, solution_;
  MatX response_;  ///< the patch's response in double precision, before it is stored
  // mass_spring
  MatX full_, system_;
  std::vector<double> area_;
  VecX border_velocity_;
  std::vector<std::int32_t> node_patch_;  ///< own_stiffness: body node → patch node (−1: none)
};

/// The contact on a patch for one frame: where, which way, how hard and how stiff.
struct PatchContact {
  std::int32_t triangle = -1;  ///< patch triangle (−1: no contact)
  Vec3 barycentric = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< out of the tissue, toward the tool
  double force = 0.0;           ///< normal force on the tool [N] (the tissue gets −force·normal)
  double stiffness = 0.0;       ///< d force / d penetration of the contact law [N/m]
  double contact_radius = 0.0;  ///< the disc the force is spread over (load_spread.hpp) [m]
};

/// The haptic-side state of a local model: the patch's current shape. It refers to the
/// newest patch in place (the channel's snapshot, runtime::DeviceChannels::patch, a
/// QuadBuffer that keeps the one before it too), so taking a new patch copies nothing and the
/// previous model can still be evaluated in the frame it is replaced.
class LocalModel {
 public:
  LocalModel(LocalModelKind kind, const PatchCapacity& capacity);

  /// Takes a newly published patch: the shape restarts from it at time `now` [s]. The model
  /// refers to `patch` until the next reset: it must stay alive and unchanged until then.
  void reset(const LocalPatch& patch, double now);
  /// Moves the border (and, for compliance, nothing else) to time `now`.
  void extrapolate(double now);
  /// Advances the free nodes over one frame of length `dt` under the contact (triangle −1:
  /// none), solving the contact force implicitly; returns the force the model settled at.
  double advance(const PatchContact& contact, double dt);

  /// Most contacts one advance() takes at once (a sphere-set finger has one or eight).
  static constexpr int kMaxContacts = 8;
  /// The same with several contacts (a sphere-set finger): each dents the patch under its own
  /// force, and the forces are solved together, since each contact's dent moves the others'
  /// points. Contacts past kMaxContacts, or with triangle −1, are left out. `settled`, when
  /// not empty, receives each contact's settled force (0 for those left out).
  void advance(std::span<const PatchContact> contacts, double dt, std::span<double> settled = {});

  [[nodiscard]] bool valid() const { return patch_->valid; }
  [[nodiscard]] const LocalPatch& patch() const { return *patch_; }
  /// The current shape (valid until the next call that changes it).
  [[nodiscard]] const SurfaceQuery& surface() const { return query_; }
  [[nodiscard]] std::span<const Vec3> positions() const {
    return {current_.data(), static_cast<std::size_t>(patch_->node_count)};
  }
  /// How far the last advance() moved the contact point: the free nodes' displacement
  /// change weighted by the load's shares, the measure of the contact's motion its implicit
  /// force solve used (zero without contact) [m].
  [[nodiscard]] const Vec3& contact_motion() const { return contact_motion_; }
  /// How far the point at `barycentric` on patch triangle `triangle` has moved from where
  /// the simulation published it [m] (zero for a triangle not in the patch).
  [[nodiscard]] Vec3 moved_since_published(std::int32_t triangle, const Vec3& barycentric) const;
  /// Where the point at `barycentric` on patch triangle `triangle` is now, and where the
  /// simulation published it [m] (NaN for a triangle not in the patch).
  [[nodiscard]] Vec3 point(std::int32_t triangle, const Vec3& barycentric) const;
  [[nodiscard]] Vec3 published_point(std::int32_t triangle, const Vec3& barycentric) const;
  /// Free-node displacement from the published shape (3·free) [m].
  [[nodiscard]] const VecX& displacement() const { return u_; }

 private:
  void place_nodes();
  /// The point at `barycentric` on patch triangle `triangle` of `vertices` (NaN off the patch).
  [[nodiscard]] Vec3 point_of(std::span<const Vec3> vertices, std::int32_t triangle, const Vec3& barycentric) const;

  LocalPatch none_;  ///< an empty patch of the capacity, until the first reset
  const LocalPatch* patch_ = &none_;
  std::vector<Vec3> current_;
  VecX u_, v_, rhs_, next_;
  MatX columns_;  ///< B·g of each contact: the free nodes' response to its unit normal force
  std::vector<LoadShare> shares_;
  Vec3 contact_motion_ = Vec3::Zero();
  double since_ = 0.0;  ///< time since the patch's shape [s]
  double now_ = 0.0;
  BruteForceSurfaceQuery query_{{}, {}};
};

}  // namespace tactus::contact
