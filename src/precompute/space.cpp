#include "precompute/space.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace tactus::precompute {

const char* to_string(PointStatus s) {
  switch (s) {
    case PointStatus::pending: return "pending";
    case PointStatus::solved: return "solved";
    case PointStatus::failed: return "failed";
    case PointStatus::unreachable: return "unreachable";
  }
  return "?";
}

void Space::allocate(std::size_t node_count) {
  const std::size_t n = grid.size();
  status.assign(n, PointStatus::pending);
  force.assign(n, Vec3::Zero());
  source.assign(n, -1);
  iterations.assign(n, 0);
  residual.assign(n, 0.0);
  seconds.assign(n, 0.0);
  reason.assign(n, std::string());
  displacement = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * node_count), static_cast<Eigen::Index>(n));
  force_gradient.assign(n, Mat3::Zero());
  torque.assign(n, Vec3::Zero());
  torque_gradient.assign(n, Mat3::Zero());
  displacement_gradient =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * node_count), static_cast<Eigen::Index>(3 * n));
  refined_points.clear();
  refined_cells.clear();
  refined_lookup_.clear();
  for (auto& cells : cell_lookup_) cells.clear();
}

bool Space::fits(const LatticeIndex& at) {
  for (const std::int32_t v : at.ijk)
    if (v < 0 || (static_cast<std::int64_t>(v) << (kMaxLevel - at.level)) >= (std::int64_t{1} << 21)) return false;
  return true;
}

std::uint64_t Space::key(const LatticeIndex& at) {
  std::uint64_t k = 0;
  for (int a = 0; a < 3; ++a) {
    const auto v = static_cast<std::uint64_t>(static_cast<std::uint32_t>(at.ijk[static_cast<std::size_t>(a)])
                                              << (kMaxLevel - at.level)) & 0x1fffffu;
    k |= v << (21 * a);
  }
  return k;
}

std::optional<std::size_t> Space::find(const LatticeIndex& at) const {
  if (at.level == 0) {  // the grid itself (the force query's common case: no division)
    if (!grid.contains(at.ijk[0], at.ijk[1], at.ijk[2])) return std::nullopt;
    return grid.index(at.ijk[0], at.ijk[1], at.ijk[2]);
  }
  const int scale = 1 << at.level;
  if (at.ijk[0] % scale == 0 && at.ijk[1] % scale == 0 && at.ijk[2] % scale == 0) {
    const int i = at.ijk[0] / scale, j = at.ijk[1] / scale, k = at.ijk[2] / scale;
    if (!grid.contains(i, j, k)) return std::nullopt;
    return grid.index(i, j, k);
  }
  if (!fits(at)) return std::nullopt;
  const auto it = refined_lookup_.find(key(at));
  if (it == refined_lookup_.end()) return std::nullopt;
  return it->second;
}

Vec3 Space::position(std::size_t p) const {
  if (p < grid.size()) return grid.point(p);
  const LatticeIndex& at = refined_points[p - grid.size()];
  return grid.origin + grid.spacing / (1 << at.level) * Vec3(at.ijk[0], at.ijk[1], at.ijk[2]);
}

bool Space::is_refined(const LatticeIndex& cell) const {
  if (cell.level < 0 || cell.level >= kMaxLevel) return false;
  const auto& cells = cell_lookup_[static_cast<std::size_t>(cell.level)];
  return !cells.empty() && fits(cell) && cells.contains(key(cell));
}

std::size_t Space::add_point(const LatticeIndex& at) {
  if (at.level < 1 || at.level > kMaxLevel) throw InputError("a refined point lies on levels 1 to " +
                                                             std::to_string(kMaxLevel));
  if (!fits(at)) throw InputError("the grid is too large to refine (at most 8,192 points along an axis)");
  const std::size_t p = status.size();
  refined_points.push_back(at);
  refined_lookup_[key(at)] = p;
  status.push_back(PointStatus::pending);
  force.push_back(Vec3::Zero());
  source.push_back(-1);
  iterations.push_back(0);
  residual.push_back(0.0);
  seconds.push_back(0.0);
  reason.emplace_back();
  force_gradient.push_back(Mat3::Zero());
  torque.push_back(Vec3::Zero());
  torque_gradient.push_back(Mat3::Zero());
  displacement.conservativeResize(Eigen::NoChange, displacement.cols() + 1);
  displacement.col(displacement.cols() - 1).setZero();
  displacement_gradient.conservativeResize(Eigen::NoChange, displacement_gradient.cols() + 3);
  displacement_gradient.rightCols<3>().setZero();
  return p;
}

void Space::refine_cell(const LatticeIndex& cell) {
  if (cell.level < 0 || cell.level >= kMaxLevel) throw InputError("a cell can be refined at most " +
                                                                   std::to_string(kMaxLevel) + " times");
  if (!fits(cell)) throw InputError("the grid is too large to refine (at most 8,192 points along an axis)");
  cell_lookup_[static_cast<std::size_t>(cell.level)].insert(key(cell));
  refined_cells.push_back(cell);
}

void Space::store(const PointResult& r) {
  status[r.point] = r.status;
  force[r.point] = r.force;
  torque[r.point] = r.status == PointStatus::solved ? r.torque : Vec3::Zero();
  source[r.point] = r.source;
  iterations[r.point] = r.iterations;
  residual[r.point] = r.residual;
  seconds[r.point] = r.seconds;
  reason[r.point] = r.reason;
  const auto p = static_cast<Eigen::Index>(r.point);
  if (r.status == PointStatus::solved && r.displacement.size() == displacement.rows())
    displacement.col(p) = r.displacement;
  else
    displacement.col(p).setZero();
  const bool with_gradient = r.status == PointStatus::solved && r.displacement_gradient.rows() == displacement.rows() &&
                             r.displacement_gradient.cols() == 3;
  force_gradient[r.point] = with_gradient ? r.force_gradient : Mat3::Zero();
  torque_gradient[r.point] = with_gradient ? r.torque_gradient : Mat3::Zero();
  if (with_gradient)
    displacement_gradient.middleCols<3>(3 * p) = r.displacement_gradient;
  else
    displacement_gradient.middleCols<3>(3 * p).setZero();
}

std::size_t Space::count(PointStatus s) const {
  return static_cast<std::size_t>(std::count(status.begin(), status.end(), s));
}

}  // namespace tactus::precompute
