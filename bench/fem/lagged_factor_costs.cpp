// What a static Newton direction costs with a fresh factorization and with an earlier one
// (docs/precompute.md, "The factorization, lagged"): on seed 001's organ (about 2,000 nodes,
// neo-Hookean, pushed 30 mm in 12 load steps), at the pushed state, the median of 5 timings
// of the exact tangent and its assembly, CHOLMOD's analysis and factorization, a substitution
// with the factor and a stiffness product, and the analysis and factorization of the engine's
// static solves, ordered on the graph of the nodes; then the conjugate-gradient iterations to 1e-8 on
// that tangent preconditioned with the factor of the tangent at 0, 1/2, 3/4 and 11/12 of the
// push.
//
//   OPENBLAS_NUM_THREADS=1 build/release/bench/lagged_factor_costs
#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "core/parallel.hpp"
#include "physics/node_ordered_cholesky.hpp"
#include "physics/getfem/getfem_harness.hpp"

using namespace tactus;
using namespace tactus::physics;
using namespace tactus::physics::getfem;
using SpMat = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

namespace {

/// The exact tangent at x, lower triangle, held dofs replaced by identity rows.
SpMat tangent(const TetFem& fem, const VecX& x, const VecX& free, Scratch& scratch) {
  const VecX v = VecX::Zero(x.size()), q;
  fem.linearize_exact(x, v, q, scratch);
  std::vector<Triplet> all, kept;
  fem.add_triplets(1.0, 0.0, all, scratch);
  for (const Triplet& t : all)
    if (t.row() >= t.col() && free[t.row()] != 0.0 && free[t.col()] != 0.0) kept.push_back(t);
  for (Eigen::Index i = 0; i < x.size(); ++i) kept.emplace_back(i, i, free[i] != 0.0 ? 0.0 : 1.0);
  SpMat a(x.size(), x.size());
  a.setFromTriplets(kept.begin(), kept.end());
  return a;
}

double median_ms(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main() {
  set_thread_limit(1);
  Case c = liver(FemLaw::neo_hookean, 0.03, 12, 2000);
  c.force_tolerance = 1e-10;
  const Solution pushed = solve_tactus(c);
  const auto fem = std::make_shared<TetFem>(c.mesh, c.material);
  VecX free = VecX::Ones(3 * static_cast<Eigen::Index>(c.mesh.vertices.size()));
  for (const auto& f : c.fixed) free[3 * f.node + f.component] = 0.0;
  const auto scratch = fem->make_scratch();
  const VecX rest = fem->rest_positions(), x = rest + pushed.u;
  const VecX b = VecX::Random(x.size()).cwiseProduct(free);

  std::vector<double> tangent_ms, analysis_ms, factor_ms, solve_ms, product_ms, node_analysis_ms, node_factor_ms;
  double nonzeros = 0.0, flops = 0.0, node_nonzeros = 0.0, node_flops = 0.0;
  for (int k = 0; k < 5; ++k) {
    Eigen::CholmodSupernodalLLT<SpMat> llt;
    const auto t0 = Clock::now();
    const SpMat a = tangent(*fem, x, free, *scratch);
    const auto ta = Clock::now();
    llt.analyzePattern(a);  // once a solve in the engine
    const auto t1 = Clock::now();
    llt.factorize(a);
    const auto t2 = Clock::now();
    const VecX y = llt.solve(b);
    const auto t3 = Clock::now();
    VecX out = VecX::Zero(x.size());
    fem->add_stiffness_product(y, out, *scratch);
    const auto t4 = Clock::now();
    const auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    tangent_ms.push_back(ms(t0, ta));
    analysis_ms.push_back(ms(ta, t1));
    factor_ms.push_back(ms(t1, t2));
    solve_ms.push_back(ms(t2, t3));
    product_ms.push_back(ms(t3, t4));
    nonzeros = llt.cholmod().lnz;
    flops = llt.cholmod().fl;
    NodeOrderedCholesky by_nodes;
    const auto t5 = Clock::now();
    by_nodes.analyze_by_nodes(a);
    const auto t6 = Clock::now();
    by_nodes.factorize(a);
    const auto t7 = Clock::now();
    node_analysis_ms.push_back(ms(t5, t6));
    node_factor_ms.push_back(ms(t6, t7));
    node_nonzeros = by_nodes.cholmod().lnz;
    node_flops = by_nodes.cholmod().fl;
  }
  std::printf("%zu nodes, %zu tets, %ld dofs; factor: %.0f nonzeros, %.3g flop\n", c.mesh.vertices.size(),
              c.mesh.tets.size(), static_cast<long>(x.size()), nonzeros, flops);
  // The tangent's assembly here sorts its triplets (setFromTriplets); the engine's fills the
  // places they landed before, which costs less.
  std::printf("medians of 5, ms: exact tangent and assembly %.1f, symbolic analysis %.1f, factorization %.1f, "
              "substitution %.2f, stiffness product %.2f\n",
              median_ms(tangent_ms), median_ms(analysis_ms), median_ms(factor_ms), median_ms(solve_ms),
              median_ms(product_ms));
  std::printf("ordered on the nodes' graph (static solves): symbolic analysis %.1f ms, factorization %.1f ms; "
              "factor: %.0f nonzeros, %.3g flop\n",
              median_ms(node_analysis_ms), median_ms(node_factor_ms), node_nonzeros, node_flops);

  const SpMat a = tangent(*fem, x, free, *scratch);
  for (const double at : {0.0, 0.5, 0.75, 11.0 / 12.0}) {
    Eigen::CholmodSupernodalLLT<SpMat> llt(tangent(*fem, rest + at * pushed.u, free, *scratch));
    VecX sol = VecX::Zero(b.size()), r = b, z = llt.solve(r), p = z;
    double rz = r.dot(z);
    int it = 0;
    for (; it < 500 && r.norm() > 1e-8 * b.norm(); ++it) {
      const VecX ap = a.selfadjointView<Eigen::Lower>() * p;
      const double alpha = rz / p.dot(ap);
      sol += alpha * p;
      r -= alpha * ap;
      z = llt.solve(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
    std::printf("factor of the tangent at %.3f of the push: %d iterations to 1e-8\n", at, it);
  }
  return 0;
}
