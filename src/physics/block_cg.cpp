#include "physics/block_cg.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <span>
#include <utility>

#include "core/parallel.hpp"

namespace tactus::physics {

namespace {

/// Inverts a symmetric positive definite 3x3 block; returns false if B is not one.
bool invert_spd(const Mat3& B, Mat3& inverse) {
  // Leading minors (Sylvester), then the adjugate over the determinant.
  const double m2 = B(0, 0) * B(1, 1) - B(0, 1) * B(1, 0);
  Mat3 adj;
  adj(0, 0) = B(1, 1) * B(2, 2) - B(1, 2) * B(2, 1);
  adj(0, 1) = B(0, 2) * B(2, 1) - B(0, 1) * B(2, 2);
  adj(0, 2) = B(0, 1) * B(1, 2) - B(0, 2) * B(1, 1);
  adj(1, 0) = B(1, 2) * B(2, 0) - B(1, 0) * B(2, 2);
  adj(1, 1) = B(0, 0) * B(2, 2) - B(0, 2) * B(2, 0);
  adj(1, 2) = B(0, 2) * B(1, 0) - B(0, 0) * B(1, 2);
  adj(2, 0) = B(1, 0) * B(2, 1) - B(1, 1) * B(2, 0);
  adj(2, 1) = B(0, 1) * B(2, 0) - B(0, 0) * B(2, 1);
  adj(2, 2) = m2;
  const double det = B(0, 0) * adj(0, 0) + B(0, 1) * adj(1, 0) + B(0, 2) * adj(2, 0);
  if (!(B(0, 0) > 0.0 && m2 > 0.0 && det > 0.0)) return false;
  inverse = adj / det;
  return true;
}

/// out += B in (Sign 1) or out -= B in (Sign -1), B or B^T (Transposed) a 3x3 block of a
/// BlockMatrix: plain scalar code, inlined in the loops below.
template <bool Transposed, int Sign>
inline void add_product(const Mat3& B, const double* in, double* out) {
  const double* b = B.data();  // column-major
  for (int i = 0; i < 3; ++i) {
    const double sum = Transposed ? b[3 * i] * in[0] + b[3 * i + 1] * in[1] + b[3 * i + 2] * in[2]
                                  : b[i] * in[0] + b[i + 3] * in[1] + b[i + 6] * in[2];
    out[i] += Sign * sum;
  }
}

/// Sizes the scratch for A and splits its nodes into ranges of about equal work (a node and
/// its upper blocks); finds the separator (the nodes coupled to a later range) and the lists
/// of blocks the sweeps read from the other side of it.
void prepare(const BlockMatrix& A, Eigen::Index dofs, BlockCgScratch& w) {
  for (VecX* v : {&w.residual, &w.rhat, &w.z, &w.p, &w.t, &w.u, &w.lower})
    if (v->size() != dofs) *v = VecX::Zero(dofs);
  const std::size_t nodes = A.diagonal.size();
  w.diagonal.resize(nodes);
  w.inverse.resize(nodes);
  const std::size_t chosen = w.ranges > 0 ? w.ranges : A.sweep_ranges;
  const std::size_t ranges = chosen > 0 ? std::min(chosen, std::max<std::size_t>(nodes, 1)) : block_cg_ranges(nodes);
  if (w.pattern == A.row_start.data() && w.pattern_blocks == A.column.size() && w.bound.size() == ranges + 1 &&
      static_cast<std::size_t>(w.bound.back()) == nodes)
    return;
  auto row = [&](std::size_t i) {
    return std::pair{static_cast<std::size_t>(A.row_start[i]), static_cast<std::size_t>(A.row_start[i + 1])};
  };
  w.bound.assign(ranges + 1, 0);
  const double total = static_cast<double>(nodes + A.column.size());
  std::size_t range = 1;
  for (std::size_t i = 0; i < nodes && range < ranges; ++i) {
    const double work = static_cast<double>(i + static_cast<std::size_t>(A.row_start[i]));
    while (range < ranges && work >= total * static_cast<double>(range) / static_cast<double>(ranges))
      w.bound[range++] = static_cast<Eigen::Index>(i);
  }
  for (; range <= ranges; ++range) w.bound[range] = static_cast<Eigen::Index>(nodes);
  w.partial_rr.assign(ranges + 1, 0.0);
  w.partial_rz.assign(ranges + 1, 0.0);
  w.partial_pbp.assign(ranges + 1, 0.0);
  w.range_ok.assign(ranges, 1);

  // The blocks into each node from rows of earlier ranges (the residual's product), and the
  // separator: the nodes with a block to a later range. Upper blocks only point forwards, so
  // the interiors of two ranges never share a block.
  std::vector<std::size_t> range_of(nodes);
  for (std::size_t r = 0; r < ranges; ++r)
    for (auto i = w.bound[r]; i < w.bound[r + 1]; ++i) range_of[static_cast<std::size_t>(i)] = r;
  w.in_separator.assign(nodes, 0);
  w.cross_start.assign(nodes + 1, 0);
  for (std::size_t i = 0; i < nodes; ++i)
    for (auto [k, end] = row(i); k < end; ++k) {
      const auto j = static_cast<std::size_t>(A.column[k]);
      if (range_of[j] == range_of[i]) continue;
      ++w.cross_start[j + 1];
      w.in_separator[i] = 1;
    }
  for (std::size_t j = 0; j < nodes; ++j) w.cross_start[j + 1] += w.cross_start[j];
  w.cross_block.assign(static_cast<std::size_t>(w.cross_start[nodes]), 0);
  w.cross_row.assign(w.cross_block.size(), 0);
  std::vector<std::int32_t> next(w.cross_start.begin(), w.cross_start.end() - 1);
  for (std::size_t i = 0; i < nodes; ++i)
    for (auto [k, end] = row(i); k < end; ++k) {
      const auto j = static_cast<std::size_t>(A.column[k]);
      if (range_of[j] == range_of[i]) continue;
      const auto slot = static_cast<std::size_t>(next[j]++);
      w.cross_block[slot] = static_cast<std::int32_t>(k);
      w.cross_row[slot] = static_cast<std::int32_t>(i);
    }

  // The sweeps' order: the separator first, then each range's interior. Blocks stored in a row
  // whose node is on the other side (separator or interior) of their column's, for that column.
  w.separator.clear();
  w.interior.clear();
  w.interior_start.assign(ranges + 1, 0);
  for (std::size_t r = 0; r < ranges; ++r) {
    for (auto i = w.bound[r]; i < w.bound[r + 1]; ++i)
      (w.in_separator[static_cast<std::size_t>(i)] ? w.separator : w.interior).push_back(static_cast<std::int32_t>(i));
    w.interior_start[r + 1] = static_cast<std::int32_t>(w.interior.size());
  }
  w.across_start.assign(nodes + 1, 0);
  for (std::size_t i = 0; i < nodes; ++i)
    for (auto [k, end] = row(i); k < end; ++k) {
      const auto j = static_cast<std::size_t>(A.column[k]);
      if (w.in_separator[j] != w.in_separator[i]) ++w.across_start[j + 1];
    }
  for (std::size_t j = 0; j < nodes; ++j) w.across_start[j + 1] += w.across_start[j];
  w.across_block.assign(static_cast<std::size_t>(w.across_start[nodes]), 0);
  w.across_row.assign(w.across_block.size(), 0);
  next.assign(w.across_start.begin(), w.across_start.end() - 1);
  for (std::size_t i = 0; i < nodes; ++i)
    for (auto [k, end] = row(i); k < end; ++k) {
      const auto j = static_cast<std::size_t>(A.column[k]);
      if (w.in_separator[j] == w.in_separator[i]) continue;
      const auto slot = static_cast<std::size_t>(next[j]++);
      w.across_block[slot] = static_cast<std::int32_t>(k);
      w.across_row[slot] = static_cast<std::int32_t>(i);
    }
  w.pattern = A.row_start.data();
  w.pattern_blocks = A.column.size();
}

}  // namespace

std::size_t block_cg_ranges(std::size_t nodes) {
  // One thread sweeps the separator while the others wait, and it grows with the ranges:
  // two ranges up to 32k nodes (on the 24^3 cube, 82,944 tets, the step took 179 ns per tet
  // with two ranges, 191 with four and 206 with eight on two threads).
  if (nodes < 2048) return 1;
  if (nodes < 32768) return 2;
  return nodes < 131072 ? 4 : 8;
}

int solve_block_cg(const BlockMatrix& A, const VecX& free_mask, double tolerance, int max_iterations, const VecX& rhs,
                   VecX& x, BlockCgScratch& w) {
  prepare(A, x.size(), w);
  const double* mask = free_mask.data();
  x.array() *= free_mask.array();
  w.residual = rhs.cwiseProduct(free_mask);
  const double rhs_norm = w.residual.norm();
  if (rhs_norm == 0.0) {
    x.setZero();
    return 0;
  }
  const double target = tolerance * rhs_norm;
  const std::size_t ranges = w.bound.size() - 1;
  const char* in_separator = w.in_separator.data();

  auto block = [&](std::int32_t k) -> const Mat3& { return A.upper[static_cast<std::size_t>(k)]; };
  auto column = [&](std::int32_t k) { return A.column[static_cast<std::size_t>(k)]; };
  auto row_begin = [&](Eigen::Index i) { return A.row_start[static_cast<std::size_t>(i)]; };
  auto row_end = [&](Eigen::Index i) { return A.row_start[static_cast<std::size_t>(i) + 1]; };
  auto separated = [&](std::int32_t node) { return in_separator[node] != 0; };
  /// out += sum of B in_j over the blocks stored in other rows j (transposed) on the other
  /// side of the separator from node i.
  auto add_across = [&](Eigen::Index i, const double* in, double* out) {
    for (auto c = w.across_start[static_cast<std::size_t>(i)]; c < w.across_start[static_cast<std::size_t>(i) + 1]; ++c)
      add_product<true, 1>(block(w.across_block[static_cast<std::size_t>(c)]),
                           in + 3 * Eigen::Index{w.across_row[static_cast<std::size_t>(c)]}, out);
  };
  auto sum = [&](const std::vector<double>& partial) {
    double s = 0.0;
    for (double v : partial) s += v;
    return s;
  };
  const auto separator = std::span<const std::int32_t>(w.separator);
  auto interior = [&](std::size_t r) {
    return std::span<const std::int32_t>(w.interior).subspan(
        static_cast<std::size_t>(w.interior_start[r]),
        static_cast<std::size_t>(w.interior_start[r + 1] - w.interior_start[r]));
  };
  // Forward sweep over the separator (first in the order): y = W^-1 y in place on its rows,
  // each taking its share out of the later separator rows; with t, also (L t) there.
  auto forward_separator = [&](double* y, const double* t, double* lower) {
    for (const std::int32_t node : separator) {
      const Eigen::Index i = node;
      double* yi = y + 3 * i;
      const double s[3] = {yi[0], yi[1], yi[2]};
      yi[0] = yi[1] = yi[2] = 0.0;
      add_product<false, 1>(w.inverse[static_cast<std::size_t>(i)], s, yi);
      for (auto k = row_begin(i); k < row_end(i); ++k) {
        if (!separated(column(k))) continue;
        add_product<true, -1>(block(k), yi, y + 3 * Eigen::Index{column(k)});
        if (t) add_product<true, 1>(block(k), t + 3 * i, lower + 3 * Eigen::Index{column(k)});
      }
    }
  };

  int iterations = 0;
  bool singular = false;
  // Four syncs an iteration; each partial sum has its own array, written once between two
  // reads of it that a sync separates. Slot `ranges` of each is the separator's.
  run_team(static_cast<unsigned>(ranges), [&](unsigned member, Team& team) {
    // Member m sweeps ranges [first, last): a fixed share, whatever the team's size.
    const std::size_t first = ranges * member / team.members(), last = ranges * (member + 1) / team.members();
    double* t = w.t.data();
    double* u = w.u.data();          // W^-1 (p^ - D t), then B p^ = t + u
    double* lower = w.lower.data();  // L t
    double* rhat = w.rhat.data();

    // Node blocks and their inverses, fixed dofs decoupled; the residual rhs - A x (row i of
    // a range takes its upper blocks' products, hands the transposed ones to the later rows
    // of its range and gathers those from earlier ranges).
    for (std::size_t r = first; r < last; ++r) {
      const Eigen::Index begin = w.bound[r], end = w.bound[r + 1];
      w.range_ok[r] = 1;
      for (Eigen::Index i = begin; i < end; ++i) {
        Mat3 D = A.diagonal[static_cast<std::size_t>(i)];
        for (Eigen::Index k = 0; k < 3; ++k)
          if (mask[3 * i + k] == 0.0) {
            D.row(k).setZero();
            D.col(k).setZero();
            D(k, k) = 1.0;
          }
        Mat3& inverse = w.inverse[static_cast<std::size_t>(i)];
        if (!invert_spd(D, inverse)) w.range_ok[r] = 0;
        for (Eigen::Index k = 0; k < 3; ++k)
          if (mask[3 * i + k] == 0.0) D(k, k) = inverse(k, k) = 0.0;  // the rest of row and column k is zero
        w.diagonal[static_cast<std::size_t>(i)] = D;
      }
      for (Eigen::Index i = begin; i < end; ++i) {
        double* ri = w.residual.data() + 3 * i;
        const double* xi = x.data() + 3 * i;
        for (auto c = w.cross_start[static_cast<std::size_t>(i)]; c < w.cross_start[static_cast<std::size_t>(i) + 1]; ++c)
          add_product<true, -1>(block(w.cross_block[static_cast<std::size_t>(c)]),
                                x.data() + 3 * Eigen::Index{w.cross_row[static_cast<std::size_t>(c)]}, ri);
        add_product<false, -1>(A.diagonal[static_cast<std::size_t>(i)], xi, ri);
        for (auto k = row_begin(i); k < row_end(i); ++k) {
          const Eigen::Index j = column(k);
          add_product<false, -1>(block(k), x.data() + 3 * j, ri);
          if (j < end) add_product<true, -1>(block(k), xi, w.residual.data() + 3 * j);
        }
      }
      auto residual = w.residual.segment(3 * begin, 3 * (end - begin));
      residual.array() *= free_mask.segment(3 * begin, 3 * (end - begin)).array();
      w.partial_rr[r] = residual.squaredNorm();
      w.rhat.segment(3 * begin, 3 * (end - begin)) = residual;
    }
    team.sync();
    if (std::find(w.range_ok.begin(), w.range_ok.end(), 0) != w.range_ok.end()) {
      if (member == 0) singular = true;
      return;
    }
    // The transformed residual r^ = W^-1 r: the separator, then each interior (its rows take
    // the separator's share, then hand theirs to the later rows of the interior); z = D r^.
    auto z_of = [&](std::span<const std::int32_t> nodes) {
      double rz = 0.0;
      for (const std::int32_t node : nodes) {
        const Eigen::Index i = node;
        double* zi = w.z.data() + 3 * i;
        zi[0] = zi[1] = zi[2] = 0.0;
        add_product<false, 1>(w.diagonal[static_cast<std::size_t>(i)], rhat + 3 * i, zi);
        for (int d = 0; d < 3; ++d) rz += rhat[3 * i + d] * zi[d];
      }
      return rz;
    };
    if (member == 0) {
      forward_separator(rhat, nullptr, nullptr);
      w.partial_rz[ranges] = z_of(separator);
    }
    team.sync();
    for (std::size_t r = first; r < last; ++r) {
      for (const std::int32_t node : interior(r)) {
        const Eigen::Index i = node;
        double* ri = rhat + 3 * i;
        double s[3] = {ri[0], ri[1], ri[2]};
        if (ranges > 1) {
          double c[3] = {0.0, 0.0, 0.0};
          add_across(i, rhat, c);
          for (auto k = row_begin(i); k < row_end(i); ++k)
            if (separated(column(k))) add_product<false, 1>(block(k), rhat + 3 * Eigen::Index{column(k)}, c);
          for (int d = 0; d < 3; ++d) s[d] -= c[d];
        }
        ri[0] = ri[1] = ri[2] = 0.0;
        add_product<false, 1>(w.inverse[static_cast<std::size_t>(i)], s, ri);
        for (auto k = row_begin(i); k < row_end(i); ++k)
          if (!separated(column(k))) add_product<true, -1>(block(k), ri, rhat + 3 * Eigen::Index{column(k)});
      }
      w.partial_rz[r] = z_of(interior(r));
      const Eigen::Index begin = 3 * w.bound[r], length = 3 * (w.bound[r + 1] - w.bound[r]);
      w.p.segment(begin, length) = w.z.segment(begin, length);
    }
    team.sync();
    double rr = sum(w.partial_rr), rz = sum(w.partial_rz);

    int it = 0;
    for (; it < max_iterations && std::sqrt(rr) > target; ++it) {
      // Backward sweep, W^T t = p^, the interiors first (last in the order): row i gathers its
      // upper blocks' products with the later t of its interior.
      for (std::size_t r = first; r < last; ++r) {
        const auto nodes = interior(r);
        for (auto n = nodes.rbegin(); n != nodes.rend(); ++n) {
          const Eigen::Index i = *n;
          double s[3] = {w.p[3 * i], w.p[3 * i + 1], w.p[3 * i + 2]};
          for (auto k = row_begin(i); k < row_end(i); ++k)
            if (!separated(column(k))) add_product<false, -1>(block(k), t + 3 * Eigen::Index{column(k)}, s);
          double* ti = t + 3 * i;
          ti[0] = ti[1] = ti[2] = 0.0;
          add_product<false, 1>(w.inverse[static_cast<std::size_t>(i)], s, ti);
        }
      }
      team.sync();
      // The separator backward (all its blocks to interiors and to later separator rows), then
      // forward: W u = p^ - D t there, with L t.
      if (member == 0) {
        for (auto n = separator.rbegin(); n != separator.rend(); ++n) {
          const Eigen::Index i = *n;
          double s[3] = {w.p[3 * i], w.p[3 * i + 1], w.p[3 * i + 2]};
          double c[3] = {0.0, 0.0, 0.0};
          add_across(i, t, c);
          for (int d = 0; d < 3; ++d) s[d] -= c[d];
          for (auto k = row_begin(i); k < row_end(i); ++k)
            add_product<false, -1>(block(k), t + 3 * Eigen::Index{column(k)}, s);
          double* ti = t + 3 * i;
          ti[0] = ti[1] = ti[2] = 0.0;
          add_product<false, 1>(w.inverse[static_cast<std::size_t>(i)], s, ti);
        }
        for (const std::int32_t node : separator) {
          const Eigen::Index i = node;
          for (int d = 0; d < 3; ++d) lower[3 * i + d] = 0.0;
          for (int d = 0; d < 3; ++d) u[3 * i + d] = w.p[3 * i + d];
          add_product<false, -1>(w.diagonal[static_cast<std::size_t>(i)], t + 3 * i, u + 3 * i);
        }
        forward_separator(u, t, lower);
        // B p^ = t + u there once the interiors have read u (the update adds t).
        double pBp = 0.0;
        for (const std::int32_t node : separator)
          for (Eigen::Index d = 3 * Eigen::Index{node}; d < 3 * Eigen::Index{node} + 3; ++d) pBp += w.p[d] * (u[d] + t[d]);
        w.partial_pbp[ranges] = pBp;
      }
      team.sync();
      // Forward sweep over the interiors, W u = p^ - D t, and L t with the same blocks (the
      // separator's share gathered, the interior's handed on); B p^ = t + u.
      for (std::size_t r = first; r < last; ++r) {
        const auto nodes = interior(r);
        for (const std::int32_t node : nodes)
          for (Eigen::Index d = 3 * Eigen::Index{node}; d < 3 * Eigen::Index{node} + 3; ++d) u[d] = lower[d] = 0.0;
        double pBp = 0.0;
        for (const std::int32_t node : nodes) {
          const Eigen::Index i = node;
          double* ui = u + 3 * i;
          const double* ti = t + 3 * i;
          double s[3] = {w.p[3 * i] + ui[0], w.p[3 * i + 1] + ui[1], w.p[3 * i + 2] + ui[2]};
          add_product<false, -1>(w.diagonal[static_cast<std::size_t>(i)], ti, s);
          if (ranges > 1) {
            double cu[3] = {0.0, 0.0, 0.0}, ct[3] = {0.0, 0.0, 0.0};
            add_across(i, u, cu);
            add_across(i, t, ct);
            for (auto k = row_begin(i); k < row_end(i); ++k)
              if (separated(column(k))) {
                add_product<false, 1>(block(k), u + 3 * Eigen::Index{column(k)}, cu);
                add_product<false, 1>(block(k), t + 3 * Eigen::Index{column(k)}, ct);
              }
            for (int d = 0; d < 3; ++d) {
              s[d] -= cu[d];
              lower[3 * i + d] += ct[d];
            }
          }
          ui[0] = ui[1] = ui[2] = 0.0;
          add_product<false, 1>(w.inverse[static_cast<std::size_t>(i)], s, ui);
          for (auto k = row_begin(i); k < row_end(i); ++k) {
            if (separated(column(k))) continue;
            add_product<true, -1>(block(k), ui, u + 3 * Eigen::Index{column(k)});
            add_product<true, 1>(block(k), ti, lower + 3 * Eigen::Index{column(k)});
          }
          for (int d = 0; d < 3; ++d) {
            ui[d] += ti[d];
            pBp += w.p[3 * i + d] * ui[d];
          }
        }
        w.partial_pbp[r] = pBp;
      }
      team.sync();
      const double pBp = sum(w.partial_pbp);
      if (!(pBp > 0.0)) break;  // not positive definite along p: keep the best so far
      const double alpha = rz / pBp;
      // x += alpha W^-T p^ = alpha t; A t = W B p^ = p^ + L t, so r -= alpha (p^ + L t).
      if (member == 0) w.partial_rz[ranges] = 0.0;  // the separator's rows are in their ranges' sums here
      for (std::size_t r = first; r < last; ++r) {
        double rr_part = 0.0, rz_part = 0.0;
        for (Eigen::Index i = w.bound[r]; i < w.bound[r + 1]; ++i) {
          if (separated(static_cast<std::int32_t>(i)))
            for (Eigen::Index d = 3 * i; d < 3 * i + 3; ++d) u[d] += t[d];
          for (Eigen::Index d = 3 * i; d < 3 * i + 3; ++d) {
            x[d] += alpha * t[d];
            w.residual[d] -= alpha * (w.p[d] + lower[d]) * mask[d];
            rr_part += w.residual[d] * w.residual[d];
            w.rhat[d] -= alpha * u[d];
          }
          double* zi = w.z.data() + 3 * i;
          zi[0] = zi[1] = zi[2] = 0.0;
          add_product<false, 1>(w.diagonal[static_cast<std::size_t>(i)], w.rhat.data() + 3 * i, zi);
          for (int d = 0; d < 3; ++d) rz_part += w.rhat[3 * i + d] * zi[d];
        }
        w.partial_rr[r] = rr_part;
        w.partial_rz[r] = rz_part;
      }
      team.sync();
      rr = sum(w.partial_rr);
      const double rz_next = sum(w.partial_rz);
      const double beta = rz_next / rz;
      for (std::size_t r = first; r < last; ++r) {
        const Eigen::Index begin = 3 * w.bound[r], length = 3 * (w.bound[r + 1] - w.bound[r]);
        w.p.segment(begin, length) = w.z.segment(begin, length) + beta * w.p.segment(begin, length);
      }
      rz = rz_next;
    }
    if (member == 0) iterations = it;
  });
  return singular ? -1 : iterations;
}

}  // namespace tactus::physics
