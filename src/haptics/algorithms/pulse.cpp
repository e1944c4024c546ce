#include "haptics/algorithms/pulse.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tactus::haptics {

PulseForce::PulseForce(PulseConfig config) : config_(std::move(config)) {
  if (!(config_.rate > 0.0) || !std::isfinite(config_.rate)) throw std::invalid_argument("pulse rate must be > 0");
  if (!(config_.duty_cycle > 0.0 && config_.duty_cycle < 1.0))
    throw std::invalid_argument("pulse duty_cycle must be in (0, 1)");
  if (!(config_.amplitude > 0.0) || !std::isfinite(config_.amplitude))
    throw std::invalid_argument("pulse amplitude must be > 0");
  if (!(config_.range > 0.0) || !std::isfinite(config_.range)) throw std::invalid_argument("pulse range must be > 0");
  if (config_.sources.empty()) throw std::invalid_argument("a pulse needs at least one source");
  for (const Vec3& s : config_.sources)
    if (!s.allFinite()) throw std::invalid_argument("pulse source is not finite");
}

bool PulseForce::beating(double t) const {
  if (!std::isfinite(t)) return false;
  const double beats = t * config_.rate / 60.0;
  return beats - std::floor(beats) < config_.duty_cycle;
}

double PulseForce::weight(const Vec3& tool, const Vec3& push) const {
  if (!tool.allFinite() || !push.allFinite()) return 0.0;
  double best = 0.0;
  for (const Vec3& source : config_.sources) {
    const Vec3 to_tool = tool - source;
    const double d = to_tool.norm();
    if (!(d < config_.range)) continue;
    const double fade = (1.0 - d / config_.range) * (1.0 - d / config_.range);
    // On the source itself every direction points away from it.
    const double facing = d > 1e-12 ? std::max(0.0, push.dot(to_tool) / d) : 1.0;
    best = std::max(best, fade * facing);
  }
  return std::min(best, 1.0);
}

Vec3 PulseForce::force(double t, const Vec3& tool, const Vec3& contact_force) const {
  const double pressing = contact_force.norm();
  if (!(pressing > 0.0) || !std::isfinite(pressing) || !beating(t)) return Vec3::Zero();
  const Vec3 push = contact_force / pressing;
  return config_.amplitude * weight(tool, push) * push;
}

std::vector<Vec3> pulse_sources_along_axis(std::span<const Vec3> nodes, int count) {
  if (nodes.empty()) throw std::invalid_argument("pulse sources: the body has no node");
  if (count < 1) throw std::invalid_argument("pulse sources: need at least one");
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : nodes) centroid += p;
  centroid /= static_cast<double>(nodes.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : nodes) covariance += (p - centroid) * (p - centroid).transpose();
  // Eigenvalues come in increasing order: the last vector is the principal axis. A single
  // node (or a round blob) still gives some unit vector, and a zero extent along it.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Vec3 axis = solver.eigenvectors().col(2).normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& p : nodes) {
    const double s = axis.dot(p - centroid);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  std::vector<Vec3> sources;
  sources.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const double s = lo + (hi - lo) * (k + 0.5) / count;
    sources.push_back(centroid + s * axis);
  }
  return sources;
}

}  // namespace tactus::haptics
