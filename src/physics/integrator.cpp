// Time integration and static solves for any ForceModel.
#include <omp.h>

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "physics/block_cg.hpp"
#include "physics/body.hpp"
#include "physics/node_ordered_cholesky.hpp"

namespace tactus::physics {

void ForceModel::add_damping_product(const VecX&, VecX&, const Scratch&) const {}
double ForceModel::min_volume_ratio(const VecX&) const { return std::numeric_limits<double>::infinity(); }
void ForceModel::update_internal(const VecX&, double, VecX&, Scratch&) const {}

void ForceModel::add_mass_product(double scale, const VecX& in, VecX& out) const {
  out += scale * lumped_mass().cwiseProduct(in);
}

void ForceModel::add_mass_triplets(double scale, std::vector<Triplet>& out) const {
  const VecX& m = lumped_mass();
  for (Eigen::Index i = 0; i < m.size(); ++i) out.emplace_back(i, i, scale * m[i]);
}

bool ForceModel::add_matrix_values(double, double, double, std::span<const std::int32_t>, double*,
                                   const Scratch&) const {
  return false;
}

bool ForceModel::linearize_exact(const VecX&, const VecX&, const VecX&, Scratch&) const { return false; }

const BlockMatrix* ForceModel::assemble_system(double, double, double, Scratch&) const { return nullptr; }

void ForceModel::linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                                   Scratch& s) const {
  forces(x, v, q, f, s);
  linearize(x, v, q, s);
  add_stiffness_product(dx, f, s);
}

void ForceModel::add_system_product(double a, double b, double c, const VecX& in, VecX& out, const Scratch& s) const {
  // The products take unscaled inputs: scale a copy, kept per thread so that repeated calls
  // allocate nothing once it is sized.
  thread_local VecX scaled;
  add_mass_product(a, in, out);
  if (b != 0.0) {
    scaled = b * in;
    add_damping_product(scaled, out, s);
  }
  scaled = c * in;
  add_stiffness_product(scaled, out, s);
}

void Body::fix_nodes(const std::vector<std::int32_t>& nodes) {
  fixed_dofs.resize(3 * model->node_count(), 0);
  for (auto n : nodes) {
    if (n < 0 || static_cast<std::size_t>(n) >= model->node_count())
      throw std::out_of_range("fix_nodes: node " + std::to_string(n) + " out of range");
    for (int k = 0; k < 3; ++k) fixed_dofs[3 * static_cast<std::size_t>(n) + k] = 1;
  }
}

std::size_t Body::fixed_node_count() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i + 2 < fixed_dofs.size(); i += 3) n += fixed_dofs[i] != 0;
  return n;
}

struct SolverScratch {
  VecX force, rhs, delta, residual, z, p, Ap, diag, x_trial, v_trial;
  /// The last three velocity changes of implicit steps (newest first), CG's starting guess.
  VecX warm, warm_previous, warm_older;
  BlockCgScratch block_cg;  ///< assembled systems (solve_block_cg)
  int warm_count = 0;  ///< how many of warm, warm_previous, warm_older hold one
  std::vector<Triplet> triplets;
  SparseMatrix matrix;
  /// Where each of the last assembly's triplets landed in matrix's values (assemble_matrix).
  std::vector<Eigen::Index> scatter;
  /// build_pattern's work arrays: triplets bucketed by column, and per row its place in the
  /// column being built (and which column that was).
  std::vector<std::int32_t> by_column, column_next, row_place, row_column;
  /// Where each triplet the model appends lands in matrix's values (−1: a dropped upper or
  /// fixed entry), for models that reassemble from values alone (add_matrix_values); the
  /// diagonal's place for each dof; and whether the mass triplets followed the model's.
  std::vector<std::int32_t> slots;
  std::vector<std::int32_t> diagonal_slots;
  bool slots_with_mass = false;
  bool values_refused = false;  ///< the model offers no add_matrix_values: keep no slots
  NodeOrderedCholesky cholesky;
  bool pattern_analyzed = false;
  /// cholesky holds a factorized stiffness tangent (a static solve's), which preconditions
  /// the tangents of the iterations and load steps after it (solve_lagged).
  bool stiffness_factor = false;
  /// Iterations the last solve_lagged took with this factor (0 after a factorization).
  int lagged_iterations = 0;
  long factorizations = 0;  ///< every Cholesky factorization so far
  /// The step length whose implicit system M + hD + h²K cholesky holds (0: none, or another
  /// system), and how many steps have used that factor since it was made.
  double step_factor_h = 0.0;
  int step_factor_uses = 0;
  VecX free_mask;  // 1 for free dofs, 0 for fixed
  // Contact springs: each one's push per newton on the dofs (u), the system's response to it
  // (W = A⁻¹u, kept as the next step's warm start) and the loads an explicit step applies.
  std::array<VecX, kMaxContactSprings> spring_push, spring_response;
  VecX loads;
  /// Whether the last linear solve took the matrix-free path (known after the first one).
  bool matrix_free = false, path_known = false;
  /// Contact springs folded into the matrix-free operator as rank-one terms w·u·uᵀ (0: none).
  std::array<double, kMaxContactSprings> folded_weight{};
  std::size_t folded = 0;
};

namespace {

/// Adds the time of a scope to one part of the state's StepProfile, where it has one.
class ProfileScope {
 public:
  ProfileScope(const BodyState& s, double StepProfile::*part) : profile_(s.profile), part_(part) {
    if (profile_) start_ = std::chrono::steady_clock::now();
  }
  ~ProfileScope() {
    if (profile_) profile_->*part_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ProfileScope(const ProfileScope&) = delete;
  ProfileScope& operator=(const ProfileScope&) = delete;

 private:
  StepProfile* profile_;
  double StepProfile::*part_;
  std::chrono::steady_clock::time_point start_{};
};

void zero_fixed(const Body& body, VecX& v) {
  if (body.fixed_dofs.empty()) return;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (body.fixed_dofs[static_cast<std::size_t>(i)]) v[i] = 0.0;
}

/// f += external forces and weight.
void add_loads(const Body& body, const VecX& f_ext, VecX& f) {
  if (f_ext.size() == f.size()) f += f_ext;
  if (!body.gravity.isZero()) {
    const VecX& m = body.model->lumped_mass();
    for (Eigen::Index i = 0; i < f.size(); ++i) f[i] += m[i] * body.gravity[i % 3];
  }
}

/// Total force: internal + external + gravity, written to f.
void total_force(const Body& body, const VecX& x, const VecX& v, const VecX& q, const VecX& f_ext,
                 BodyState& s, VecX& f) {
  f.resize(x.size());  // no-op (no allocation) once sized
  body.model->forces(x, v, q, f, *s.model_scratch);
  add_loads(body, f_ext, f);
}

/// Debian's CHOLMOD is built with OpenMP: each factorization runs its bookkeeping loops
/// (clearing its map, zeroing and filling supernodes) in parallel regions of a fixed 4
/// threads (a num_threads clause, which OMP_NUM_THREADS does not change). On a 2-core
/// machine, or beside other work, libgomp's workers sleep between regions, so every region
/// cost futex wake-ups and context switches: `tactus curves` on the upper leg spent 16.6 s of
/// its 38 s in the kernel with 3 million voluntary switches (docs/BENCHMARKS.md, "System
/// time"). The arithmetic is OpenBLAS's (its own threads), so these regions run on the
/// calling thread alone: OpenMP's max-active-levels is 0 on every thread that factorizes (a
/// per-thread setting in libgomp). The loops write disjoint entries: the factor is the same
/// bits with any team size.
void cholmod_without_openmp_teams() {
  thread_local bool done = false;
  if (done) return;
  omp_set_max_active_levels(0);
  done = true;
}

/// w.matrix (n × n, compressed, rows sorted in each column) with the pattern of w.triplets,
/// their values summed in triplet order, and w.scatter (each triplet's place in the values).
/// Linear in the triplets: they are bucketed by column, each column's distinct rows found with
/// a per-row marker and sorted (a few dozen a column), where a general sparse build would sort
/// or transpose every triplet.
void build_pattern(SolverScratch& w, Eigen::Index n) {
  const std::size_t count = w.triplets.size();
  const auto columns = static_cast<std::size_t>(n);
  w.column_next.assign(columns + 1, 0);
  for (const Triplet& t : w.triplets) ++w.column_next[static_cast<std::size_t>(t.col()) + 1];
  for (std::size_t c = 0; c < columns; ++c) w.column_next[c + 1] += w.column_next[c];
  w.by_column.resize(count);
  for (std::size_t k = 0; k < count; ++k)
    w.by_column[static_cast<std::size_t>(w.column_next[static_cast<std::size_t>(w.triplets[k].col())]++)] =
        static_cast<std::int32_t>(k);
  // column_next[c] is now column c's end, column c − 1's start its begin.
  w.row_column.assign(columns, -1);
  w.row_place.resize(columns);
  w.scatter.resize(count);
  w.matrix.resize(n, n);
  w.matrix.resizeNonZeros(static_cast<Eigen::Index>(count));  // at most; trimmed below
  int* starts = w.matrix.outerIndexPtr();
  int* rows = w.matrix.innerIndexPtr();
  int nonzeros = 0;
  for (std::size_t c = 0; c < columns; ++c) {
    starts[c] = nonzeros;
    const std::size_t begin = c == 0 ? 0 : static_cast<std::size_t>(w.column_next[c - 1]);
    const std::size_t end = static_cast<std::size_t>(w.column_next[c]);
    for (std::size_t i = begin; i < end; ++i) {
      const auto row = static_cast<std::size_t>(w.triplets[static_cast<std::size_t>(w.by_column[i])].row());
      if (w.row_column[row] == static_cast<std::int32_t>(c)) continue;
      w.row_column[row] = static_cast<std::int32_t>(c);
      rows[nonzeros++] = static_cast<int>(row);
    }
    std::sort(rows + starts[c], rows + nonzeros);
    for (int p = starts[c]; p < nonzeros; ++p) w.row_place[static_cast<std::size_t>(rows[p])] = p;
    for (std::size_t i = begin; i < end; ++i) {
      const auto k = static_cast<std::size_t>(w.by_column[i]);
      w.scatter[k] = w.row_place[static_cast<std::size_t>(w.triplets[k].row())];
    }
  }
  starts[columns] = nonzeros;
  w.matrix.resizeNonZeros(nonzeros);
  double* values = w.matrix.valuePtr();
  std::fill(values, values + nonzeros, 0.0);
  for (std::size_t k = 0; k < count; ++k) values[w.scatter[k]] += w.triplets[k].value();
}

/// Sums w.triplets into w.matrix (n × n). The first assembly, or one whose triplets fall on
/// other entries, builds the pattern (build_pattern) and records where each one landed; the
/// next ones, whose models emit the same entries in the same order, add each value at its
/// recorded place. Both sum an entry's duplicates in triplet order, so the matrix has the
/// same bits either way, without rebuilding the pattern, which took a fifth of a static
/// Newton iteration.
void assemble_matrix(SolverScratch& w, Eigen::Index n) {
  const std::size_t count = w.triplets.size();
  if (w.scatter.size() == count && w.matrix.rows() == n && w.matrix.isCompressed()) {
    double* values = w.matrix.valuePtr();
    const int* rows = w.matrix.innerIndexPtr();
    const int* starts = w.matrix.outerIndexPtr();
    std::fill(values, values + w.matrix.nonZeros(), 0.0);
    bool same = true;
    for (std::size_t k = 0; k < count && same; ++k) {
      const Triplet& t = w.triplets[k];
      const Eigen::Index p = w.scatter[k];
      same = rows[p] == t.row() && p >= starts[t.col()] && p < starts[t.col() + 1];
      values[p] += t.value();
    }
    if (same) return;
  }
  build_pattern(w, n);
}

/// After assemble_matrix: w.slots held, for each triplet of the model, its index among the
/// kept ones (the first `kept` of the assembly's, the dofs' diagonal after them) or −1; now
/// its place in the matrix's values.
void record_slots(SolverScratch& w, std::size_t kept, bool with_mass) {
  if (w.matrix.nonZeros() > std::numeric_limits<std::int32_t>::max()) {
    w.slots.clear();
    return;
  }
  for (std::int32_t& slot : w.slots)
    if (slot >= 0) slot = static_cast<std::int32_t>(w.scatter[static_cast<std::size_t>(slot)]);
  w.diagonal_slots.resize(w.scatter.size() - kept);
  for (std::size_t i = 0; i < w.diagonal_slots.size(); ++i)
    w.diagonal_slots[i] = static_cast<std::int32_t>(w.scatter[kept + i]);
  w.slots_with_mass = with_mass;
}

/// Reassembles w.matrix (a·M + b·D + c·K, lower triangle, fixed dofs on the identity) from
/// the model's values alone where its pattern is known (w.slots) and the model offers them:
/// no triplets to build, filter and sort. Adds in the order the triplet assembly does, so
/// the matrix has the same bits. Returns false where it cannot.
bool assemble_from_values(const ForceModel& model, double a, double b, double c, SolverScratch& w,
                          const Scratch& ms, Eigen::Index n) {
  if (w.slots.empty() || w.slots_with_mass != (a != 0.0) || w.matrix.rows() != n || !w.matrix.isCompressed() ||
      w.diagonal_slots.size() != static_cast<std::size_t>(n))
    return false;
  double* values = w.matrix.valuePtr();
  std::fill(values, values + w.matrix.nonZeros(), 0.0);
  if (!model.add_matrix_values(c, b, a, w.slots, values, ms)) {
    w.values_refused = true;
    w.slots.clear();
    return false;
  }
  for (Eigen::Index i = 0; i < n; ++i)
    values[w.diagonal_slots[static_cast<std::size_t>(i)]] += w.free_mask[i] != 0.0 ? 0.0 : 1.0;
  return true;
}

/// Solves (a·M + b·D + c·K) x = rhs over the free dofs, linearized already. CG warm starts
/// from x's incoming value. Returns the number of iterations (0 for Cholesky).
int solve_linear(const Body& body, BodyState& s, double a, double b, double c, const VecX& rhs,
                 VecX& x) {
  const ForceModel& model = *body.model;
  SolverScratch& w = *s.solver_scratch;
  const VecX& m = model.lumped_mass();
  const Scratch& ms = *s.model_scratch;

  if (body.settings.solver == LinearSolver::cholesky) {
    cholmod_without_openmp_teams();
    std::optional<ProfileScope> timed(std::in_place, s, &StepProfile::assembly);
    const auto n = static_cast<Eigen::Index>(m.size());
    if (!assemble_from_values(model, a, b, c, w, ms, n)) {
      w.triplets.clear();
      model.add_triplets(c, b, w.triplets, ms);
      if (a != 0.0) model.add_mass_triplets(a, w.triplets);
      // Fixed dofs: drop their rows and columns and put 1 on the diagonal, so x = 0 there.
      // Only the lower triangle: the factorization reads no other (Eigen's Cholmod classes
      // take the Lower half by default), and half the entries are half the assembly.
      const bool with_slots = !w.values_refused;
      w.slots.assign(with_slots ? w.triplets.size() : 0, -1);
      std::size_t keep = 0;
      for (std::size_t k = 0; k < w.triplets.size(); ++k) {
        const Triplet& t = w.triplets[k];
        if (t.row() >= t.col() && w.free_mask[t.row()] != 0.0 && w.free_mask[t.col()] != 0.0) {
          if (with_slots) w.slots[k] = static_cast<std::int32_t>(keep);
          w.triplets[keep++] = t;
        }
      }
      w.triplets.resize(keep);
      for (Eigen::Index i = 0; i < n; ++i) w.triplets.emplace_back(i, i, w.free_mask[i] != 0.0 ? 0.0 : 1.0);
      assemble_matrix(w, n);
      if (with_slots) record_slots(w, keep, a != 0.0);
    }
    timed.emplace(s, &StepProfile::solve);
    if (!w.pattern_analyzed) {
      // METIS draws from one random generator for the whole process, seeded at each call:
      // two analyses at once (the precompute's workers) would draw from each other's
      // sequence and order their matrices, and so round their factors, by timing.
      static std::mutex analysis;
      const std::lock_guard<std::mutex> one_at_a_time(analysis);
      // An indefinite matrix is reported through info() below (the static solve expects it
      // of an exact tangent), not printed by CHOLMOD.
      w.cholesky.cholmod().print = 0;
      // A static solve factorizes a few times per analysis, so the cheaper analysis pays; an
      // implicit step's matrix is factorized every step for the life of the scene, so CHOLMOD
      // chooses the order with the least fill (it tries AMD and METIS on the dofs).
      if (a == 0.0 && b == 0.0)
        w.cholesky.analyze_by_nodes(w.matrix);
      else
        w.cholesky.analyzePattern(w.matrix);
      w.pattern_analyzed = true;
    }
    w.cholesky.factorize(w.matrix);
    ++w.factorizations;
    w.step_factor_h = 0.0;
    w.matrix_free = false;
    w.path_known = true;
    w.stiffness_factor = a == 0.0 && b == 0.0 && c == 1.0 && w.cholesky.info() == Eigen::Success;
    w.lagged_iterations = 0;
    if (w.cholesky.info() != Eigen::Success)
      throw std::runtime_error("sparse Cholesky failed: the system matrix is not positive definite");
    x = w.cholesky.solve(rhs.cwiseProduct(w.free_mask));
    return 0;
  }

  w.path_known = true;
  w.matrix_free = false;
  const BlockMatrix* assembled = nullptr;
  {
    const ProfileScope timed(s, &StepProfile::assembly);
    assembled = model.assemble_system(a, b, c, *s.model_scratch);
  }
  if (assembled) {
    const ProfileScope timed(s, &StepProfile::solve);
    const int it = solve_block_cg(*assembled, w.free_mask, body.settings.cg_tolerance, body.settings.cg_max_iterations,
                                  rhs, x, w.block_cg);
    if (it >= 0) return it;
  }
  w.matrix_free = true;

  // Jacobi-preconditioned conjugate gradients on the free dofs, matrix-free. The lumped mass
  // stands in for the mass's diagonal: a consistent mass is spectrally equivalent to it.
  auto apply = [&](const VecX& in, VecX& out) {
    out.setZero();
    model.add_system_product(a, b, c, in, out, ms);
    for (std::size_t j = 0; j < w.folded; ++j)
      if (w.folded_weight[j] > 0.0) out += (w.folded_weight[j] * w.spring_push[j].dot(in)) * w.spring_push[j];
    out.array() *= w.free_mask.array();
  };
  const ProfileScope timed(s, &StepProfile::solve);
  w.diag = a * m;
  model.add_diagonal(c, b, w.diag, ms);
  for (std::size_t j = 0; j < w.folded; ++j) w.diag += w.folded_weight[j] * w.spring_push[j].cwiseAbs2();
  for (Eigen::Index i = 0; i < w.diag.size(); ++i)
    if (!(w.diag[i] > 0.0)) w.diag[i] = 1.0;  // guards indefinite or empty rows

  x.array() *= w.free_mask.array();
  apply(x, w.Ap);
  w.residual = rhs.cwiseProduct(w.free_mask) - w.Ap;
  const double rhs_norm = rhs.cwiseProduct(w.free_mask).norm();
  if (rhs_norm == 0.0) {
    x.setZero();
    return 0;
  }
  const double target = body.settings.cg_tolerance * rhs_norm;
  w.z = w.residual.cwiseQuotient(w.diag);
  w.p = w.z;
  double rz = w.residual.dot(w.z);
  int it = 0;
  for (; it < body.settings.cg_max_iterations && w.residual.norm() > target; ++it) {
    apply(w.p, w.Ap);
    const double pAp = w.p.dot(w.Ap);
    if (!(pAp > 0.0)) break;  // not positive definite along p: keep the best so far
    const double alpha = rz / pAp;
    x += alpha * w.p;
    w.residual -= alpha * w.Ap;
    w.z = w.residual.cwiseQuotient(w.diag);
    const double rz_next = w.residual.dot(w.z);
    w.p = w.z + (rz_next / rz) * w.p;
    rz = rz_next;
  }
  return it;
}

/// solve_lagged's stopping point for a Newton direction, relative to the residual it balances:
/// Newton's convergence stays quadratic until the residual nears this fraction of itself.
constexpr double kLaggedForcing = 1e-3;

/// Most iterations solve_lagged may take. Each costs a substitution with the factor and a
/// stiffness product; assembling and factorizing a tangent afresh costs about ten of them
/// (2,125-node organ, one thread: 2.7 ms against 22 ms for the factorization alone,
/// bench/lagged_factor_costs).
constexpr int kMaxLaggedIterations = 10;
/// A factor whose last solve took this many iterations has aged (the tangents drifted from
/// it over the load steps): the next solve factorizes afresh, and the ones after it take a
/// few iterations again. 7 rather than 5: on the 2,125-node organ of bench/static_vs_getfem
/// the StVK and neo-Hookean pushes factorize 2, 3 and 5 times instead of 4, 5 and 9, at the
/// same Newton iterations and 3–15 % less CPU (docs/BENCHMARKS.md).
constexpr int kAgedFactorIterations = 7;

/// Solves K·x = rhs on the free dofs, K the tangent the model last linearized, by conjugate
/// gradients preconditioned with the Cholesky factor of an earlier stiffness tangent (an
/// iteration or a load step before), until |K·x − rhs| ≤ target. Newton's tangents change
/// little from one iteration or load step to the next, so a few iterations stand in for a
/// factorization. Returns false, x undefined, where no such factor is in hand, a direction
/// shows non-positive curvature (K is not definite), the target is not met within
/// kMaxLaggedIterations, or the factor has aged: the caller factorizes then.
bool solve_lagged(const Body& body, BodyState& s, const VecX& rhs, double target, VecX& x) {
  SolverScratch& w = *s.solver_scratch;
  if (!w.stiffness_factor || w.lagged_iterations >= kAgedFactorIterations) return false;
  const ForceModel& model = *body.model;
  const ProfileScope timed(s, &StepProfile::solve);
  auto apply = [&](const VecX& in, VecX& out) {
    out.setZero();
    model.add_stiffness_product(in, out, *s.model_scratch);
    out.array() *= w.free_mask.array();
  };
  x.setZero(rhs.size());
  w.residual = rhs.cwiseProduct(w.free_mask);
  if (w.residual.norm() <= target) return true;
  w.cholesky.solve_into(w.residual, w.z);
  w.z.array() *= w.free_mask.array();
  w.p = w.z;
  double rz = w.residual.dot(w.z);
  w.lagged_iterations = kMaxLaggedIterations;  // what a failure below leaves
  for (int it = 0; it < kMaxLaggedIterations; ++it) {
    apply(w.p, w.Ap);
    const double curvature = w.p.dot(w.Ap);
    if (!(curvature > 0.0) || !(rz > 0.0)) return false;
    const double alpha = rz / curvature;
    x += alpha * w.p;
    w.residual -= alpha * w.Ap;
    if (w.residual.norm() <= target) {
      w.lagged_iterations = it + 1;
      return x.allFinite();
    }
    w.cholesky.solve_into(w.residual, w.z);
    w.z.array() *= w.free_mask.array();
    const double rz_next = w.residual.dot(w.z);
    w.p = w.z + (rz_next / rz) * w.p;
    rz = rz_next;
  }
  return false;
}

/// Solves the stiffness tangent the model last linearized, K·x = rhs on the free dofs: with
/// the factor in hand to `target` where it serves (solve_lagged), else by a fresh solve.
void solve_stiffness(const Body& body, BodyState& s, const VecX& rhs, double target, VecX& x) {
  if (solve_lagged(body, s, rhs, target, x)) return;
  x.setZero(rhs.size());
  solve_linear(body, s, 0.0, 0.0, 1.0, rhs, x);
}

/// w.free_mask from the body's fixed dofs: 1 on free dofs, 0 on fixed ones.
void read_free_mask(const Body& body, SolverScratch& w, Eigen::Index n) {
  w.free_mask.setOnes(n);
  for (std::size_t i = 0; i < body.fixed_dofs.size() && static_cast<Eigen::Index>(i) < n; ++i)
    if (body.fixed_dofs[i]) w.free_mask[static_cast<Eigen::Index>(i)] = 0.0;
}

void prepare(const Body& body, BodyState& s) {
  if (!s.solver_scratch) s.solver_scratch = std::make_shared<SolverScratch>();
  SolverScratch& w = *s.solver_scratch;
  const auto n = s.x.size();
  if (w.free_mask.size() != n) {
    read_free_mask(body, w, n);
    // Sized once so that stepping allocates nothing.
    for (VecX* v : {&w.warm, &w.warm_previous, &w.warm_older, &w.force, &w.rhs, &w.delta, &w.residual, &w.z,
                    &w.p, &w.Ap, &w.diag, &w.x_trial, &w.v_trial})
      *v = VecX::Zero(n);
  }
}

/// Explicit integrators divide by the mass: they need a diagonal one.
void require_diagonal_mass(const Body& body, const char* integrator) {
  if (!body.model->mass_is_diagonal())
    throw std::invalid_argument(std::string(integrator) +
                                " needs a lumped (diagonal) mass matrix; use implicit_euler with a consistent mass");
}

/// Each spring's push per newton on the dofs, u = Σ share·direction at its nodes (free dofs only).
void build_spring_pushes(BodyState& s, std::span<const ContactSpring> springs) {
  SolverScratch& w = *s.solver_scratch;
  for (std::size_t j = 0; j < springs.size(); ++j) {
    VecX& u = w.spring_push[j];
    u.setZero(s.x.size());  // allocates on a spring slot's first use only
    for (const NodeShare& n : springs[j].nodes)
      if (n.node >= 0 && 3 * static_cast<Eigen::Index>(n.node) + 2 < u.size())
        u.segment<3>(3 * static_cast<Eigen::Index>(n.node)) += n.share * springs[j].direction;
    u.array() *= w.free_mask.array();
    if (w.spring_response[j].size() != u.size()) w.spring_response[j] = VecX::Zero(u.size());
  }
}

/// A spring's push when the step ends with velocity v, F0 − k·h·uᵀv: its nodes moved h·v.
/// Below zero it would pull (and is let go).
template <class V>
double push_at(const SolverScratch& w, const ContactSpring& spring, std::size_t j, const Eigen::MatrixBase<V>& v,
               double h) {
  return spring.force - std::max(0.0, spring.stiffness) * h * w.spring_push[j].dot(v);
}

/// Couples the springs into an implicit step's linear solve. `delta` holds A⁻¹r for the
/// step's right-hand side r without the springs (A the system matrix just solved with), and
/// the step would end with velocity v_base + delta. With the springs' pushes F at the end of
/// the step, whose nodes moved h·v:
///   v = v_base + delta + h·Σ_j F_j·W_j,  W_j = A⁻¹u_j,  F_i = F0_i − k_i·h·u_iᵀv,
/// i.e. (I + h²·K·C)·F = F0 − h·K·uᵀ(v_base + delta) with C_ij = u_iᵀW_j, solved exactly; a
/// spring that would pull is let go and the rest solved again. Adds h·Σ F_j·W_j to `delta`,
/// writes each spring's force_end and returns the linear iterations spent.
int couple_springs(const Body& body, BodyState& s, double h, std::span<ContactSpring> springs, const VecX& v_base,
                   VecX& delta) {
  SolverScratch& w = *s.solver_scratch;
  const std::size_t m = springs.size();
  int iterations = 0;
  for (std::size_t j = 0; j < m; ++j) {
    if (body.settings.solver == LinearSolver::cholesky)
      w.spring_response[j] = w.cholesky.solve(w.spring_push[j]);  // the factor solve_linear left
    else
      iterations += solve_linear(body, s, 1.0, h, h * h, w.spring_push[j], w.spring_response[j]);
  }
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxContactSprings, kMaxContactSprings>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxContactSprings, 1>;
  const auto n = static_cast<Eigen::Index>(m);
  Small coupling(n, n);
  SmallVec free_force(n), force = SmallVec::Zero(n);
  w.v_trial = v_base + delta;
  for (Eigen::Index i = 0; i < n; ++i) {
    const ContactSpring& c = springs[static_cast<std::size_t>(i)];
    const double k = std::max(0.0, c.stiffness);
    free_force[i] = push_at(w, c, static_cast<std::size_t>(i), w.v_trial, h);
    for (Eigen::Index j = 0; j < n; ++j)
      coupling(i, j) = h * h * k * w.spring_push[static_cast<std::size_t>(i)].dot(w.spring_response[static_cast<std::size_t>(j)]);
  }
  std::array<bool, kMaxContactSprings> active{};
  active.fill(true);
  for (Eigen::Index round = 0; round < n; ++round) {
    Small system = Small::Identity(n, n);
    SmallVec rhs = SmallVec::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!active[static_cast<std::size_t>(i)]) continue;  // F_i = 0
      for (Eigen::Index j = 0; j < n; ++j)
        if (active[static_cast<std::size_t>(j)]) system(i, j) += coupling(i, j);
      rhs[i] = free_force[i];
    }
    force = system.partialPivLu().solve(rhs);
    Eigen::Index most_negative = -1;
    for (Eigen::Index i = 0; i < n; ++i)
      if (active[static_cast<std::size_t>(i)] && !springs[static_cast<std::size_t>(i)].bilateral && force[i] < 0.0 &&
          (most_negative < 0 || force[i] < force[most_negative]))
        most_negative = i;
    if (most_negative < 0) break;
    active[static_cast<std::size_t>(most_negative)] = false;
  }
  for (Eigen::Index j = 0; j < n; ++j) {
    double f = force[j];
    const bool pulls = f < 0.0 && !springs[static_cast<std::size_t>(j)].bilateral;
    if (!active[static_cast<std::size_t>(j)] || !std::isfinite(f) || pulls) f = 0.0;
    delta += (h * f) * w.spring_response[static_cast<std::size_t>(j)];
    springs[static_cast<std::size_t>(j)].force_end = f;
  }
  return iterations;
}

/// Where the matrix-free path solves: the springs folded into the operator instead, as
/// rank-one terms h²·k_j·u_j·u_jᵀ, and their pushes at v_base into `rhs`:
///   (A + h²·Σ k_j·u_j·u_jᵀ)·delta = rhs + h·Σ (F0_j − k_j·h·u_jᵀv_base)·u_j,
/// the same coupling as couple_springs at the cost of one solve, not one per spring.
void fold_springs(BodyState& s, double h, std::span<const ContactSpring> springs, const VecX& v_base, VecX& rhs) {
  SolverScratch& w = *s.solver_scratch;
  w.folded = springs.size();
  for (std::size_t j = 0; j < springs.size(); ++j) {
    w.folded_weight[j] = h * h * std::max(0.0, springs[j].stiffness);
    rhs += (h * push_at(w, springs[j], j, v_base, h)) * w.spring_push[j];
  }
}

/// After a solve with the springs folded in: each spring's push at the end of the step. A
/// spring that would pull is unfolded (its push and its term taken out again) and the step
/// solved again from where it got; returns the linear iterations spent on that.
int settle_folded(const Body& body, BodyState& s, double h, std::span<ContactSpring> springs, const VecX& v_base,
                  VecX& rhs, VecX& delta) {
  SolverScratch& w = *s.solver_scratch;
  std::array<bool, kMaxContactSprings> let_go{};
  int iterations = 0;
  for (std::size_t round = 0; round <= springs.size(); ++round) {
    std::size_t most_negative = springs.size();
    double lowest = 0.0;
    for (std::size_t j = 0; j < springs.size(); ++j) {
      if (let_go[j]) continue;
      const double f = push_at(w, springs[j], j, v_base + delta, h);
      springs[j].force_end = springs[j].bilateral ? f : std::max(0.0, f);
      if (f < lowest && !springs[j].bilateral) lowest = f, most_negative = j;
    }
    if (most_negative == springs.size()) break;
    rhs -= (h * push_at(w, springs[most_negative], most_negative, v_base, h)) * w.spring_push[most_negative];
    w.folded_weight[most_negative] = 0.0;
    let_go[most_negative] = true;
    iterations += solve_linear(body, s, 1.0, h, h * h, rhs, delta);
  }
  w.folded = 0;
  return iterations;
}

void explicit_step(const Body& body, BodyState& s, double h, const VecX& f_ext, bool symplectic) {
  require_diagonal_mass(body, symplectic ? "symplectic_euler" : "explicit_euler");
  SolverScratch& w = *s.solver_scratch;
  total_force(body, s.x, s.v, s.q, f_ext, s, w.force);
  w.force.array() /= body.model->lumped_mass().array();  // acceleration
  zero_fixed(body, w.force);
  if (symplectic) {
    s.v += h * w.force;
    s.x += h * s.v;
  } else {
    s.x += h * s.v;
    s.v += h * w.force;
  }
}

void rk4_step(const Body& body, BodyState& s, double h, const VecX& f_ext) {
  require_diagonal_mass(body, "rk4");
  SolverScratch& w = *s.solver_scratch;
  const VecX& m = body.model->lumped_mass();
  auto accel = [&](const VecX& x, const VecX& v, VecX& out) {
    total_force(body, x, v, s.q, f_ext, s, out);
    out.array() /= m.array();
    zero_fixed(body, out);
  };
  // Stages kept in local vectors: RK4 is for small offline models, not the haptic path.
  VecX k1x = s.v, k1v, k2x, k2v, k3x, k3v, k4x, k4v;
  accel(s.x, s.v, k1v);
  k2x = s.v + 0.5 * h * k1v;
  accel(s.x + 0.5 * h * k1x, k2x, k2v);
  k3x = s.v + 0.5 * h * k2v;
  accel(s.x + 0.5 * h * k2x, k3x, k3v);
  k4x = s.v + h * k3v;
  accel(s.x + h * k3x, k4x, k4v);
  s.x += (h / 6.0) * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
  s.v += (h / 6.0) * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
  (void)w;
}

/// One implicit Euler step of length h. With `may_refuse`, a step that would turn an element
/// inside out (min_volume_ratio from > 0 to ≤ 0) is not taken: the state is left as it was
/// and the function returns false, for the caller to take two half steps instead.
bool implicit_step(const Body& body, BodyState& s, double h, const VecX& f_ext, std::span<ContactSpring> springs,
                   bool may_refuse) {
  SolverScratch& w = *s.solver_scratch;
  const ForceModel& model = *body.model;
  const int warm_count = w.warm_count;
  // First iteration, linearized at (x_n, v_n) (Baraff & Witkin 1998):
  //   (M + hD + h²K) Δv = h (f_n − h K v_n)
  w.z = -h * s.v;
  // The exact tangent of hyperelastic laws where the direct solver finds M + hD + h²K
  // definite (the mass outweighs a compressed element's negative stiffness at the scenes'
  // steps): no per-element projection to pay for (scenes/liver.toml's step took half the time
  // then, docs/BENCHMARKS.md). Else, and for CG, the projected tangent.
  const bool try_exact = body.settings.solver == LinearSolver::cholesky;
  // A frozen factor: with A = M + hD + h²K the matrix of the step that factorized, the
  // linearized step A·Δv = h(f_n − hK·v_n) is A·v_{n+1} = M·v_n + h·(f_e(x_n) + f_ext), f_e
  // the forces without damping (A − h²K = M + hD): the forces at x_n and one substitution.
  // The tangent lags by up to factor_reuse_steps − 1 steps; the step stays first order.
  const bool reuse = body.settings.can_reuse_factor() && w.step_factor_h == h &&
                     w.step_factor_uses < body.settings.factor_reuse_steps;
  bool exact = false;
  if (reuse) {
    {
      const ProfileScope timed(s, &StepProfile::forces);
      w.Ap.setZero();  // the velocity the forces see: no damping
      model.forces(s.x, w.Ap, s.q, w.rhs, *s.model_scratch);
    }
    add_loads(body, f_ext, w.rhs);
    w.rhs *= h;
    model.add_mass_product(1.0, s.v, w.rhs);
    w.rhs.array() *= w.free_mask.array();
    {
      const ProfileScope timed(s, &StepProfile::solve);
      w.cholesky.solve_into(w.rhs, w.delta);
    }
    w.delta -= s.v;
    w.delta.array() *= w.free_mask.array();
    s.last_linear_iterations = 0;
    ++w.step_factor_uses;
  } else if (try_exact) {
    const ProfileScope timed(s, &StepProfile::forces);
    exact = model.linearize_exact(s.x, s.v, s.q, *s.model_scratch);
    if (exact) {
      model.forces(s.x, s.v, s.q, w.rhs, *s.model_scratch);
      model.add_stiffness_product(w.z, w.rhs, *s.model_scratch);  // rhs = f − h K v
    }
  }
  if (!exact && !reuse) {
    const ProfileScope timed(s, &StepProfile::forces);
    model.linearized_forces(s.x, s.v, s.q, w.z, w.rhs, *s.model_scratch);  // rhs = f − h K v
  }
  if (!reuse) {
    add_loads(body, f_ext, w.rhs);
    w.rhs *= h;
  }
  // CG starts from the last three velocity changes extrapolated by a parabola: between 1 ms
  // steps the change drifts smoothly, and on the benchmark bodies this start needs about 2
  // iterations where the last change alone needs 4 to 5 (a straight line, 3).
  if (!reuse && w.warm_count >= 3)
    w.delta = 3.0 * w.warm - 3.0 * w.warm_previous + w.warm_older;
  else if (!reuse)
    w.delta = w.warm;
  const bool fold = !reuse && !springs.empty() && w.path_known && w.matrix_free;
  if (fold) fold_springs(s, h, springs, s.v, w.rhs);
  bool solved = false;
  if (exact) {
    try {
      s.last_linear_iterations = solve_linear(body, s, 1.0, h, h * h, w.rhs, w.delta);
      solved = true;
    } catch (const std::runtime_error&) {
      const ProfileScope timed(s, &StepProfile::forces);
      model.linearized_forces(s.x, s.v, s.q, w.z, w.rhs, *s.model_scratch);
      add_loads(body, f_ext, w.rhs);
      w.rhs *= h;
    }
  }
  if (!solved && !reuse) s.last_linear_iterations = solve_linear(body, s, 1.0, h, h * h, w.rhs, w.delta);
  if (try_exact && !reuse) {
    w.step_factor_h = h;
    w.step_factor_uses = 1;
  }
  if (fold) s.last_linear_iterations += settle_folded(body, s, h, springs, s.v, w.rhs, w.delta);
  std::swap(w.warm_older, w.warm_previous);
  std::swap(w.warm_previous, w.warm);
  w.warm = w.delta;
  w.warm_count = std::min(w.warm_count + 1, 3);
  if (!springs.empty() && !fold) s.last_linear_iterations += couple_springs(body, s, h, springs, s.v, w.delta);
  w.v_trial = s.v + w.delta;
  zero_fixed(body, w.v_trial);
  s.last_newton_iterations = 1;

  // Further Newton iterations on g(v) = M (v − v_n) − h f(x_n + h v, v) = 0, their tolerance
  // relative to the force at x_n.
  double scale = 0.0;
  if (body.settings.newton_iterations > 1) {
    total_force(body, s.x, s.v, s.q, f_ext, s, w.force);
    scale = std::max(w.force.cwiseProduct(w.free_mask).norm(), 1e-300);
  }
  for (int it = 1; it < body.settings.newton_iterations; ++it) {
    w.x_trial = s.x + h * w.v_trial;
    total_force(body, w.x_trial, w.v_trial, s.q, f_ext, s, w.force);
    w.rhs = h * w.force;  // −g
    w.z = w.v_trial - s.v;
    model.add_mass_product(-1.0, w.z, w.rhs);
    w.rhs.array() *= w.free_mask.array();
    // The springs' pushes at v_trial count in the residual; the solve couples them again.
    for (std::size_t j = 0; j < springs.size(); ++j)
      w.rhs += (h * std::max(0.0, push_at(w, springs[j], j, w.v_trial, h))) * w.spring_push[j];
    if (w.rhs.norm() <= body.settings.newton_tolerance * h * scale) break;
    for (std::size_t j = 0; j < springs.size(); ++j)
      w.rhs -= (h * std::max(0.0, push_at(w, springs[j], j, w.v_trial, h))) * w.spring_push[j];
    w.delta.setZero();
    if (fold) fold_springs(s, h, springs, w.v_trial, w.rhs);
    // The exact tangent first, as in the first iteration.
    solved = false;
    if (try_exact && model.linearize_exact(w.x_trial, w.v_trial, s.q, *s.model_scratch)) {
      try {
        s.last_linear_iterations += solve_linear(body, s, 1.0, h, h * h, w.rhs, w.delta);
        solved = true;
      } catch (const std::runtime_error&) {
        w.delta.setZero();
      }
    }
    if (!solved) {
      model.linearize(w.x_trial, w.v_trial, s.q, *s.model_scratch);
      s.last_linear_iterations += solve_linear(body, s, 1.0, h, h * h, w.rhs, w.delta);
    }
    if (fold) s.last_linear_iterations += settle_folded(body, s, h, springs, w.v_trial, w.rhs, w.delta);
    else if (!springs.empty()) s.last_linear_iterations += couple_springs(body, s, h, springs, w.v_trial, w.delta);
    w.v_trial += w.delta;
    zero_fixed(body, w.v_trial);
    ++s.last_newton_iterations;
  }
  if (may_refuse) {
    w.x_trial = s.x + h * w.v_trial;
    if (model.min_volume_ratio(w.x_trial) <= 0.0 && model.min_volume_ratio(s.x) > 0.0) {
      // The warm start's history as before this step.
      std::swap(w.warm, w.warm_previous);
      std::swap(w.warm_previous, w.warm_older);
      w.warm_count = std::min(warm_count, 2);
      // A frozen factor's step is taken again with a fresh one before it is halved.
      w.step_factor_h = 0.0;
      if (reuse) return implicit_step(body, s, h, f_ext, springs, may_refuse);
      return false;
    }
  }
  s.v = w.v_trial;
  s.x += h * s.v;
  return true;
}

/// Total potential energy of a static configuration: elastic energy minus the work of the
/// external forces and of gravity (the fixed dofs' terms are constant and harmless).
double static_potential(const Body& body, const BodyState& s, const VecX& f_ext) {
  double e = body.model->elastic_energy(s.x, s.q);
  if (f_ext.size() == s.x.size()) e -= f_ext.dot(s.x);
  if (!body.gravity.isZero()) {
    const VecX& m = body.model->lumped_mass();
    for (Eigen::Index i = 0; i < s.x.size(); ++i) e -= m[i] * body.gravity[i % 3] * s.x[i];
  }
  return e;
}

}  // namespace

BodyState make_state(const Body& body) {
  BodyState s;
  s.x = body.model->rest_positions();
  s.v = VecX::Zero(s.x.size());
  s.q = VecX::Zero(static_cast<Eigen::Index>(body.model->internal_size()));
  s.model_scratch = body.model->make_scratch();
  prepare(body, s);
  return s;
}

namespace {

/// How many times an implicit step that turns an element inside out is halved (down to
/// dt / 32); a step still inverting at the last halving is taken as it is.
constexpr int kMaxStepHalvings = 5;

/// Loads for an explicit step: f_ext plus each spring's starting push, held constant.
const VecX& explicit_loads(BodyState& s, const VecX& f_ext, std::span<ContactSpring> springs) {
  if (springs.empty()) return f_ext;
  SolverScratch& w = *s.solver_scratch;
  if (f_ext.size() == s.x.size()) w.loads = f_ext;
  else w.loads.setZero(s.x.size());
  for (std::size_t j = 0; j < springs.size(); ++j) {
    w.loads += std::max(0.0, springs[j].force) * w.spring_push[j];
    springs[j].force_end = std::max(0.0, springs[j].force);
  }
  return w.loads;
}

void step_halving(const Body& body, BodyState& s, double dt, const VecX& f_ext, std::span<ContactSpring> springs,
                  int halvings) {
  prepare(body, s);
  build_spring_pushes(s, springs);
  switch (body.settings.integrator) {
    case Integrator::explicit_euler: explicit_step(body, s, dt, explicit_loads(s, f_ext, springs), false); break;
    case Integrator::symplectic_euler: explicit_step(body, s, dt, explicit_loads(s, f_ext, springs), true); break;
    case Integrator::rk4: rk4_step(body, s, dt, explicit_loads(s, f_ext, springs)); break;
    case Integrator::implicit_euler:
      // A linearized step is accurate only while the tangent at its start holds over it. A
      // load landing on a node over a thin element (a soft organ's coarse surface) can move
      // the node past the element's far side within one step: the element turns inside out,
      // the next linearization overshoots further, and in a few steps the body diverges
      // (scenes/liver.toml reached 10^13 m and then failed its Cholesky factorization). Such a
      // step is taken as two half steps, whose shorter strokes keep the elements right side out.
      if (!implicit_step(body, s, dt, f_ext, springs, halvings < kMaxStepHalvings)) {
        // The second half starts from the pushes the first ended with.
        std::array<double, kMaxContactSprings> start{};
        for (std::size_t j = 0; j < springs.size(); ++j) start[j] = springs[j].force;
        step_halving(body, s, 0.5 * dt, f_ext, springs, halvings + 1);
        for (ContactSpring& c : springs) c.force = c.force_end;
        step_halving(body, s, 0.5 * dt, f_ext, springs, halvings + 1);
        for (std::size_t j = 0; j < springs.size(); ++j) springs[j].force = start[j];
        return;
      }
      break;
  }
  zero_fixed(body, s.v);
  enforce_nodules(body.nodules, body.fixed_dofs, body.model->lumped_mass(), dt, s.x, s.v);
  body.model->update_internal(s.x, dt, s.q, *s.model_scratch);
  s.time += dt;
}

}  // namespace

void step(const Body& body, BodyState& s, double dt, const VecX& f_ext, std::span<ContactSpring> springs) {
  if (!(dt > 0.0)) throw std::invalid_argument("step: dt must be positive");
  if (springs.size() > kMaxContactSprings)
    throw std::invalid_argument("step: " + std::to_string(springs.size()) + " contact springs, at most " +
                                std::to_string(kMaxContactSprings));
  step_halving(body, s, dt, f_ext, springs, 0);
}

namespace {

/// The force scale of a static solve at s.x: the larger of the applied loads with the weight
/// (on the free dofs) and the reactions of the held dofs. w.force must hold the total force at
/// s.x, unmasked.
double static_force_scale(const SolverScratch& w, const VecX& load) {
  double held = 0.0;
  for (Eigen::Index i = 0; i < w.force.size(); ++i)
    if (w.free_mask[i] == 0.0) held += w.force[i] * w.force[i];
  return std::max(load.norm(), std::sqrt(held));
}

}  // namespace

long factorizations(const BodyState& s) { return s.solver_scratch ? s.solver_scratch->factorizations : 0; }

void fixed_dofs_changed(const Body& body, BodyState& s) {
  if (!s.solver_scratch) return;
  SolverScratch& w = *s.solver_scratch;
  read_free_mask(body, w, s.x.size());
  w.pattern_analyzed = false;  // the matrix drops other rows and columns now
  w.step_factor_h = 0.0;        // and a factor kept for the next steps holds the old ones
  w.scatter.clear();
  w.slots.clear();
}

void forget_solver_history(BodyState& s) {
  if (!s.solver_scratch) return;
  s.solver_scratch->stiffness_factor = false;
  s.solver_scratch->warm.setZero();
  s.solver_scratch->warm_count = 0;
  for (VecX& response : s.solver_scratch->spring_response) response.setZero();
}

void analyse_ahead(const Body& body, BodyState& s, double dt) {
  if (body.settings.integrator != Integrator::implicit_euler || body.settings.solver != LinearSolver::cholesky) return;
  BodyState trial = make_state(body);
  trial.x = s.x;
  trial.v = s.v;
  trial.q = s.q;
  step(body, trial, dt);
  // Only the analysis and the assembly's places are kept: the first step factorizes afresh
  // from its own state, as it would have without this.
  SolverScratch& w = *trial.solver_scratch;
  w.step_factor_h = 0.0;
  w.factorizations = 0;
  s.solver_scratch = trial.solver_scratch;
  forget_solver_history(s);
}

bool predict_static(const Body& body, BodyState& s, const VecX& previous, const VecX& f_ext) {
  prepare(body, s);
  SolverScratch& w = *s.solver_scratch;
  const ForceModel& model = *body.model;
  // The held dofs' motion since the last equilibrium.
  w.x_trial = (s.x - previous).cwiseProduct(VecX::Ones(s.x.size()) - w.free_mask);
  if (w.x_trial.isZero(0.0)) return false;
  s.v.setZero();
  total_force(body, previous, s.v, s.q, f_ext, s, w.force);
  // The exact tangent where Cholesky finds it definite (no per-element projection to pay
  // for), else the projected one.
  auto solve = [&](bool exact) {
    if (!exact)
      model.linearize(previous, s.v, s.q, *s.model_scratch);
    else if (!model.linearize_exact(previous, s.v, s.q, *s.model_scratch))
      return false;
    w.rhs.setZero();
    model.add_stiffness_product(w.x_trial, w.rhs, *s.model_scratch);
    w.rhs = w.force - w.rhs;
    try {
      solve_stiffness(body, s, w.rhs, kLaggedForcing * w.rhs.cwiseProduct(w.free_mask).norm(), w.delta);
    } catch (const std::runtime_error&) {
      return false;
    }
    return w.delta.allFinite();
  };
  if (!(body.settings.solver == LinearSolver::cholesky && solve(true)) && !solve(false)) return false;
  s.x = previous + w.x_trial + w.delta.cwiseProduct(w.free_mask);
  return true;
}

bool static_response(const Body& body, BodyState& s, const Eigen::MatrixXd& held, Eigen::MatrixXd& motion,
                     Eigen::MatrixXd& force_change) {
  prepare(body, s);
  SolverScratch& w = *s.solver_scratch;
  const ForceModel& model = *body.model;
  const auto columns = held.cols();
  motion.resize(s.x.size(), columns);
  force_change.resize(s.x.size(), columns);
  s.v.setZero();
  auto solve = [&](bool exact) {
    if (!exact)
      model.linearize(s.x, s.v, s.q, *s.model_scratch);
    else if (!model.linearize_exact(s.x, s.v, s.q, *s.model_scratch))
      return false;
    try {
      for (Eigen::Index j = 0; j < columns; ++j) {
        const VecX held_j = held.col(j).cwiseProduct(VecX::Ones(s.x.size()) - w.free_mask);
        w.rhs.setZero();
        model.add_stiffness_product(held_j, w.rhs, *s.model_scratch);
        w.rhs = -w.rhs;
        w.delta.setZero();
        // The first column factorizes; the others reuse the factor it left.
        if (j > 0 && body.settings.solver == LinearSolver::cholesky)
          w.delta = w.cholesky.solve(w.rhs.cwiseProduct(w.free_mask));
        else
          solve_linear(body, s, 0.0, 0.0, 1.0, w.rhs, w.delta);
        motion.col(j) = held_j + w.delta.cwiseProduct(w.free_mask);
        w.rhs.setZero();
        model.add_stiffness_product(motion.col(j), w.rhs, *s.model_scratch);
        force_change.col(j) = -w.rhs;
      }
    } catch (const std::runtime_error&) {
      return false;
    }
    return motion.allFinite() && force_change.allFinite();
  };
  return (body.settings.solver == LinearSolver::cholesky && solve(true)) || solve(false);
}

StaticResult solve_static(const Body& body, BodyState& s, const VecX& f_ext, const StaticSettings& settings) {
  prepare(body, s);
  SolverScratch& w = *s.solver_scratch;
  const ForceModel& model = *body.model;
  s.v.setZero();
  // The applied loads with the weight, on the free dofs: the total force at rest minus the
  // internal one there.
  total_force(body, model.rest_positions(), s.v, s.q, f_ext, s, w.force);
  VecX load = w.force;
  model.forces(model.rest_positions(), s.v, s.q, w.rhs, *s.model_scratch);
  load -= w.rhs;
  load.array() *= w.free_mask.array();

  StaticResult result;
  // Measures the out-of-balance force at s.x (left in w.force, masked) against the scale
  // there; true when it meets the tolerance or the floor.
  double scale = 0.0;
  // force_known: w.force holds the total force at s.x already (the line search's last trial).
  auto balanced = [&](bool force_known) {
    if (!force_known) total_force(body, s.x, s.v, s.q, f_ext, s, w.force);
    scale = static_force_scale(w, load);
    w.force.array() *= w.free_mask.array();
    result.residual_force = w.force.norm();
    // Nothing to measure against (no load, no reaction): only the floor in newtons decides.
    result.residual = scale > 0.0 ? result.residual_force / scale
                                  : (result.residual_force > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
    return result.residual_force <= settings.force_tolerance || result.residual <= settings.tolerance;
  };
  // A balanced state with an element turned inside out is the wrong equilibrium.
  auto finish = [&](bool converged) {
    result.converged = converged;
    if (converged && model.min_volume_ratio(s.x) <= 0.0) {
      result.converged = false;
      result.inverted = true;
    }
    return result;
  };

  // Iterations until the exact tangent is tried again after its factorization failed: 1, 2,
  // 4, ... so a solve that stays indefinite wastes a logarithmic number of factorizations.
  const bool exact_possible = body.settings.solver == LinearSolver::cholesky;
  int exact_wait = 0, exact_backoff = 1;
  bool force_known = false;
  // The potential energy at s.x where the line search computed it at its accepted point
  // (NaN: not known).
  double energy_known = std::numeric_limits<double>::quiet_NaN();
  for (int it = 0; it < settings.max_iterations; ++it) {
    result.iterations = it;
    if (balanced(force_known)) return finish(true);
    const double r = result.residual_force;
    // Inexact Newton: a direction solved by solve_lagged balances its tangent to a fraction of
    // the residual, and no finer than half of what convergence asks for.
    const double lagged_target =
        std::max(kLaggedForcing * r, 0.5 * std::max(settings.force_tolerance, settings.tolerance * scale));
    // The exact tangent where it is positive definite, which Cholesky detects: Newton then
    // converges quadratically, where the projected tangent (the fallback) converges linearly
    // once elements are compressed or stretched far.
    bool direction = false, fell_back = false;
    if (exact_possible && exact_wait > 0) {
      --exact_wait;
      fell_back = true;
    } else if (exact_possible && model.linearize_exact(s.x, s.v, s.q, *s.model_scratch)) {
      try {
        solve_stiffness(body, s, w.force, lagged_target, w.delta);
        direction = w.delta.allFinite();
      } catch (const std::runtime_error&) {
      }
      if (!direction) {
        fell_back = true;
        exact_wait = exact_backoff;
        exact_backoff *= 2;
      }
    }
    if (!direction) {
      if (fell_back) ++result.projected_iterations;
      model.linearize(s.x, s.v, s.q, *s.model_scratch);
      solve_stiffness(body, s, w.force, lagged_target, w.delta);
    }
    if (!w.delta.allFinite()) break;
    // Backtracking line search. The merit is the total potential energy (elastic minus the
    // work of the loads and weight) with an Armijo condition: along a Newton direction from a
    // positive definite (or projected) tangent it always descends, so slender bodies take full
    // steps where the residual norm would reject them. A step that lowers the residual norm is
    // accepted too, for models whose energy omits part of the force (viscous branches).
    // The energies are evaluated only where the residual alone does not accept a step (most
    // Newton steps near the answer lower it at α = 1): the same steps, fewer element passes.
    const double slope = -w.force.dot(w.delta);  // dΠ/dα at α = 0 (force = −∇Π on free dofs)
    double energy = energy_known;  // at s.x; NaN until needed
    energy_known = std::numeric_limits<double>::quiet_NaN();
    double alpha = 1.0;
    bool decreased = false;
    for (int ls = 0; ls < 20; ++ls, alpha *= 0.5) {
      w.x_trial = s.x + alpha * w.delta;
      total_force(body, w.x_trial, s.v, s.q, f_ext, s, w.rhs);
      const double trial_residual = w.rhs.cwiseProduct(w.free_mask).norm();
      if (!std::isfinite(trial_residual)) continue;
      const bool residual_down = trial_residual < r;
      bool energy_down = false;
      energy_known = std::numeric_limits<double>::quiet_NaN();
      if (!residual_down && slope < 0.0) {
        if (std::isnan(energy)) energy = static_potential(body, s, f_ext);
        std::swap(s.x, w.x_trial);
        const double e_trial = static_potential(body, s, f_ext);
        std::swap(s.x, w.x_trial);
        energy_down = std::isfinite(e_trial) && e_trial <= energy + 1e-4 * alpha * slope;
        energy_known = e_trial;  // the accepted trial's, where the search stops here
      }
      if (residual_down || energy_down) {
        decreased = true;
        break;
      }
    }
    if (!decreased) {
      // Stagnation at round-off: the residual cannot fall further along Newton's direction.
      // Internal forces of stiff, slender bodies are far larger than the load, so round-off
      // can sit above `tolerance`; accept up to kStagnationTolerance and say so.
      result.stagnated = true;
      return finish(result.residual <= kStagnationTolerance);
    }
    const double moved = alpha * w.delta.norm();
    s.x = w.x_trial;
    std::swap(w.force, w.rhs);
    force_known = true;
    if (moved <= 1e-14 * std::max(s.x.norm(), 1e-300)) {
      // The update is below double precision of the positions: nothing left to gain.
      result.iterations = it + 1;
      result.stagnated = !balanced(true);
      return finish(!result.stagnated || result.residual <= kStagnationTolerance);
    }
  }
  result.iterations = settings.max_iterations;
  return finish(balanced(force_known));
}

double kinetic_energy(const Body& body, const BodyState& s) {
  if (body.model->mass_is_diagonal()) return 0.5 * s.v.dot(body.model->lumped_mass().cwiseProduct(s.v));
  VecX mv = VecX::Zero(s.v.size());
  body.model->add_mass_product(1.0, s.v, mv);
  return 0.5 * s.v.dot(mv);
}

double potential_energy(const Body& body, const BodyState& s) {
  double e = body.model->elastic_energy(s.x, s.q);
  const VecX& m = body.model->lumped_mass();
  for (Eigen::Index i = 0; i < s.x.size(); ++i) e -= m[i] * body.gravity[i % 3] * s.x[i];
  return e;
}

}  // namespace tactus::physics
