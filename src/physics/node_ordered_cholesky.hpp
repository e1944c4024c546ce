// A sparse Cholesky factorization ordered on the mesh's nodes.
#pragma once

#include <Eigen/CholmodSupport>
#include <stdexcept>
#include <utility>
#include <vector>

#include "physics/force_model.hpp"

namespace tactus::physics {

/// CHOLMOD's supernodal Cholesky with a symbolic analysis that orders nodes, not dofs:
/// METIS finds the fill-reducing order on the graph of the matrix's 3×3 node blocks (a third
/// of the vertices, a ninth of the edges) and the order is expanded to the dofs. On the
/// 2,125-node organ the analysis takes a fraction of METIS on the dofs for a factor of about
/// the same fill (bench/lagged_factor_costs prints both). Matrices whose order is not a
/// multiple of 3, or a METIS failure, take CHOLMOD's own analysis.
class NodeOrderedCholesky : public Eigen::CholmodSupernodalLLT<SparseMatrix> {
 public:
  void analyze_by_nodes(const SparseMatrix& lower) {
    const Eigen::Index n = lower.rows();
    if (n == 0 || n % 3 != 0) return analyzePattern(lower);
    const auto nodes = static_cast<int>(n / 3);
    graph_.clear();
    for (Eigen::Index col = 0; col < lower.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(lower, col); it; ++it)
        if (it.row() / 3 >= col / 3)
          graph_.emplace_back(static_cast<int>(it.row() / 3), static_cast<int>(col / 3), 1.0);
    SparseMatrix g(nodes, nodes);
    g.setFromTriplets(graph_.begin(), graph_.end());
    cholmod_sparse graph = Eigen::viewAsCholmod(std::as_const(g).selfadjointView<Eigen::Lower>());
    node_order_.resize(static_cast<std::size_t>(nodes));
    if (!cholmod_metis(&graph, nullptr, 0, 1, node_order_.data(), &cholmod())) return analyzePattern(lower);
    order_.resize(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < node_order_.size(); ++k)
      for (std::size_t d = 0; d < 3; ++d) order_[3 * k + d] = 3 * node_order_[k] + static_cast<int>(d);
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
    cholmod_sparse a = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
    const int methods = cholmod().nmethods, ordering = cholmod().method[0].ordering;
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = CHOLMOD_GIVEN;
    m_cholmodFactor = cholmod_analyze_p(&a, order_.data(), nullptr, 0, &cholmod());
    cholmod().nmethods = methods;
    cholmod().method[0].ordering = ordering;
    if (!m_cholmodFactor) return analyzePattern(lower);
    m_isInitialized = true;
    m_info = Eigen::Success;
    m_analysisIsOk = true;
    m_factorizationIsOk = false;
  }

  NodeOrderedCholesky() = default;
  NodeOrderedCholesky(const NodeOrderedCholesky&) = delete;
  NodeOrderedCholesky& operator=(const NodeOrderedCholesky&) = delete;
  ~NodeOrderedCholesky() {
    for (cholmod_dense** d : {&x_, &y_, &e_})
      if (*d) cholmod_free_dense(d, &cholmod());
  }

  /// x = A⁻¹ b with the factor in hand, as solve(b), but into x with CHOLMOD's workspace kept
  /// from one call to the next: an inexact Newton solve substitutes dozens of times, and
  /// solve() allocates its result and CHOLMOD's work vectors at each. Throws
  /// std::runtime_error where CHOLMOD fails.
  void solve_into(const VecX& b, VecX& x) {
    cholmod_dense B{};
    B.nrow = B.nzmax = B.d = static_cast<std::size_t>(b.size());
    B.ncol = 1;
    B.x = const_cast<double*>(b.data());  // read only: CHOLMOD takes B as input
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (!m_cholmodFactor || !cholmod_solve2(CHOLMOD_A, m_cholmodFactor, &B, nullptr, &x_, nullptr, &y_, &e_, &cholmod()))
      throw std::runtime_error("CHOLMOD: substitution failed");
    x = Eigen::Map<const VecX>(static_cast<const double*>(x_->x), b.size());
  }

 private:
  cholmod_dense *x_ = nullptr, *y_ = nullptr, *e_ = nullptr;  ///< solve_into's workspace
  std::vector<Triplet> graph_;
  std::vector<int> node_order_, order_;
};

}  // namespace tactus::physics
