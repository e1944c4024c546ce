#include "mesh/curvature.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::mesh {
namespace {

using Mat2 = Eigen::Matrix2d;

/// Two unit vectors completing n to a right-handed orthonormal frame (u, w, n).
void tangent_basis(const Vec3& n, Vec3& u, Vec3& w) {
  const Vec3 seed = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  u = (seed - seed.dot(n) * n).normalized();
  w = n.cross(u);
}

/// Principal curvatures and directions of the tangent-plane tensor B (in basis u, w).
void principal_from_tensor(const Mat2& b, const Vec3& n, const Vec3& u, const Vec3& w, VertexCurvature& out) {
  Eigen::SelfAdjointEigenSolver<Mat2> eig;
  eig.computeDirect(b);  // eigenvalues ascending
  out.k1 = eig.eigenvalues()(1);
  out.k2 = eig.eigenvalues()(0);
  const Eigen::Vector2d e1 = eig.eigenvectors().col(1);
  out.direction1 = (e1(0) * u + e1(1) * w).normalized();
  out.direction2 = n.cross(out.direction1);
}

bool finite(const VertexCurvature& c) {
  return c.normal.allFinite() && std::isfinite(c.k1) && std::isfinite(c.k2) && std::isfinite(c.kmean) &&
         c.direction1.allFinite() && c.direction2.allFinite();
}

}  // namespace

CurvatureEstimator::CurvatureEstimator(const HalfEdgeMesh& mesh, int rings, CurvatureFit fit)
    : rings_(rings), fit_(fit), vertex_count_(mesh.num_vertices()) {
  if (rings < 1 || rings > kMaxRings)
    throw InputError(fmt::format("curvature estimator: rings must be in [1, {}], got {}", kMaxRings, rings));
  if (fit != CurvatureFit::least_squares && fit != CurvatureFit::taubin)
    throw InputError(fmt::format("curvature estimator: unknown fit {}", static_cast<int>(fit)));

  const auto nv = static_cast<Index>(vertex_count_);
  const auto nf = static_cast<Index>(mesh.num_faces());
  triangles_.reserve(mesh.num_faces());
  for (Index f = 0; f < nf; ++f) triangles_.push_back(mesh.face_vertices(f));

  incident_face_offsets_.assign(vertex_count_ + 1, 0);
  for (Index v = 0; v < nv; ++v) {
    mesh.for_each_outgoing(v, [&](Index h) {
      if (!mesh.is_boundary(h)) incident_faces_.push_back(mesh.face(h));
    });
    incident_face_offsets_[v + 1] = incident_faces_.size();
  }

  // Breadth-first rings with stamps instead of per-vertex visited arrays, so building the
  // tables costs O(V · neighbourhood) rather than O(V²).
  std::vector<Index> member_of(vertex_count_, -1);
  std::vector<Index> face_of(mesh.num_faces(), -1);
  std::vector<Index> frontier, next_frontier;
  neighbour_offsets_.assign(vertex_count_ + 1, 0);
  neighbour_face_offsets_.assign(vertex_count_ + 1, 0);
  for (Index p = 0; p < nv; ++p) {
    const std::size_t first = neighbours_.size();
    member_of[p] = p;
    frontier.assign(1, p);
    for (int r = 0; r < rings && !frontier.empty(); ++r) {
      next_frontier.clear();
      for (Index u : frontier)
        mesh.for_each_outgoing(u, [&](Index h) {
          const Index w = mesh.target(h);
          if (member_of[w] != p) {
            member_of[w] = p;
            next_frontier.push_back(w);
          }
        });
      neighbours_.insert(neighbours_.end(), next_frontier.begin(), next_frontier.end());
      std::swap(frontier, next_frontier);
    }
    neighbour_offsets_[p + 1] = neighbours_.size();

    const auto add_faces_of = [&](Index u) {
      for (std::size_t i = incident_face_offsets_[u]; i < incident_face_offsets_[u + 1]; ++i) {
        const Index f = incident_faces_[i];
        if (face_of[f] == p) continue;
        const Triangle& t = triangles_[f];
        if (member_of[t[0]] == p && member_of[t[1]] == p && member_of[t[2]] == p) {
          face_of[f] = p;
          neighbour_faces_.push_back(f);
        }
      }
    };
    add_faces_of(p);
    for (std::size_t i = first; i < neighbours_.size(); ++i) add_faces_of(neighbours_[i]);
    neighbour_face_offsets_[p + 1] = neighbour_faces_.size();
  }
}

std::span<const Index> CurvatureEstimator::neighbourhood(Index v) const {
  return {neighbours_.data() + neighbour_offsets_[v], neighbour_offsets_[v + 1] - neighbour_offsets_[v]};
}

std::span<const Index> CurvatureEstimator::neighbourhood_faces(Index v) const {
  return {neighbour_faces_.data() + neighbour_face_offsets_[v],
          neighbour_face_offsets_[v + 1] - neighbour_face_offsets_[v]};
}

void CurvatureEstimator::check_positions(std::span<const Vec3> positions) const {
  if (positions.size() != vertex_count_)
    throw InputError(fmt::format("curvature estimate: {} positions given for a mesh of {} vertices",
                                 positions.size(), vertex_count_));
}

Vec3 CurvatureEstimator::vertex_normal(std::span<const Vec3> positions, Index v) const {
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = incident_face_offsets_[v]; i < incident_face_offsets_[v + 1]; ++i) {
    const Triangle& t = triangles_[incident_faces_[i]];
    const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    const Vec3 e1 = positions[t[(k + 1) % 3]] - positions[v];
    const Vec3 e2 = positions[t[(k + 2) % 3]] - positions[v];
    const Vec3 n = e1.cross(e2);
    const double len = n.norm();
    if (len == 0.0) continue;
    sum += std::atan2(len, e1.dot(e2)) * n / len;  // the corner angle as weight
  }
  const double len = sum.norm();
  return len > 0.0 ? Vec3(sum / len) : Vec3::Zero();
}

VertexCurvature CurvatureEstimator::estimate(std::span<const Vec3> positions, Index vertex) const {
  check_positions(positions);
  if (vertex < 0 || static_cast<std::size_t>(vertex) >= vertex_count_)
    throw InputError(fmt::format("curvature estimate: vertex {} out of range (mesh has {} vertices)", vertex,
                                 vertex_count_));
  return estimate_unchecked(positions, vertex);
}

VertexCurvature CurvatureEstimator::estimate_unchecked(std::span<const Vec3> positions, Index p) const {
  const VertexCurvature none;
  const auto nbrs = neighbourhood(p);
  const auto faces = neighbourhood_faces(p);
  if (nbrs.empty() || faces.empty()) return none;
  const Vec3& x = positions[p];

  // The neighbourhood's own length scale makes the weights independent of units and density.
  double sigma = 0.0;
  for (Index v : nbrs) sigma += (positions[v] - x).norm();
  sigma /= static_cast<double>(nbrs.size());
  if (!(sigma > 0.0) || !std::isfinite(sigma)) return none;

  // Normal voting (Page et al.): each face votes the normal at p of the circular arc that
  // leaves its centroid with its normal, i.e. its normal mirrored in the bisector plane of
  // centroid and p (exact on a sphere). Votes are weighted by relative area and by
  // exp(−distance / sigma); the normal is the principal eigenvector of their covariance.
  double max_area = 0.0;
  for (Index f : faces) {
    const Triangle& t = triangles_[f];
    max_area = std::max(max_area, (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).norm());
  }
  if (!(max_area > 0.0) || !std::isfinite(max_area)) return none;
  Mat3 covariance = Mat3::Zero();
  Vec3 orientation = Vec3::Zero();
  for (Index f : faces) {
    const Triangle& t = triangles_[f];
    const Vec3 n2 = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    const double area2 = n2.norm();
    if (area2 == 0.0) continue;
    const Vec3 n = n2 / area2;
    const Vec3 to_p = x - (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0;
    const double dist = to_p.norm();
    Vec3 vote = n;
    if (dist > 0.0) {
      const Vec3 u = to_p / dist;
      vote = n - 2.0 * n.dot(u) * u;
    }
    const double weight = (area2 / max_area) * std::exp(-dist / sigma);
    covariance += weight * vote * vote.transpose();
    orientation += weight * n;
  }
  Eigen::SelfAdjointEigenSolver<Mat3> normal_eig;
  normal_eig.computeDirect(covariance);
  Vec3 normal = normal_eig.eigenvectors().col(2).normalized();  // largest eigenvalue
  if (normal.dot(orientation) < 0.0) normal = -normal;
  if (!normal.allFinite() || orientation.squaredNorm() == 0.0) return none;

  // Curvature voting (eq. 7–8): toward each neighbour v_i the normal curvature of the
  // normal section through p and v_i is the turning angle Δθ of the normal over the arc
  // length Δs. For a circular arc with chord c, Δs = c·(Δθ/2)/sin(Δθ/2), hence
  // k_i = 2·sin(Δθ/2)/c; Δθ is signed by T_i·n_i, positive when the normal turns toward
  // the direction of travel (convex for an outward normal).
  Vec3 u, w;
  tangent_basis(normal, u, w);
  Mat3 normal_matrix = Mat3::Zero();  // least squares: Σ ω φφᵀ with φ = (c², 2cs, s²)
  Vec3 rhs = Vec3::Zero();
  Mat2 taubin = Mat2::Zero();  // eq. 6: Σ ω k T Tᵀ
  double weight_sum = 0.0;
  for (Index v : nbrs) {
    const Vec3 pv = positions[v] - x;
    const double chord = pv.norm();
    const Vec3 t = pv - normal.dot(pv) * normal;
    const double t_len = t.norm();
    if (!(t_len > 1e-12 * chord)) continue;  // straight above p: no tangent direction
    const Vec3 dir = t / t_len;
    const Vec3 binormal = normal.cross(dir);
    const Vec3 nv = vertex_normal(positions, v);
    const Vec3 n_in_plane = nv - binormal.dot(nv) * binormal;
    if (!(n_in_plane.norm() > 1e-12)) continue;
    const double dtheta = std::atan2(dir.dot(n_in_plane), normal.dot(n_in_plane));
    const double k = 2.0 * std::sin(0.5 * dtheta) / chord;
    const double weight = std::exp(-chord / sigma);
    const double c = dir.dot(u), s = dir.dot(w);
    const Vec3 phi(c * c, 2.0 * c * s, s * s);
    normal_matrix += weight * phi * phi.transpose();
    rhs += weight * k * phi;
    const Eigen::Vector2d d2(c, s);
    taubin += weight * k * d2 * d2.transpose();
    weight_sum += weight;
  }
  if (!(weight_sum > 0.0)) return none;

  VertexCurvature out;
  out.normal = normal;
  bool solved = false;
  if (fit_ == CurvatureFit::least_squares) {
    // Directions spanning fewer than three independent φ (all votes along one or two
    // lines) leave the tensor undetermined; Taubin's map still gives an answer then.
    Eigen::SelfAdjointEigenSolver<Mat3> conditioning;
    conditioning.computeDirect(normal_matrix, Eigen::EigenvaluesOnly);
    const Vec3 lambda = conditioning.eigenvalues();
    if (lambda(0) > 1e-8 * lambda(2)) {
      const Vec3 abc = normal_matrix.ldlt().solve(rhs);
      Mat2 b;
      b << abc(0), abc(1), abc(1), abc(2);
      principal_from_tensor(b, normal, u, w, out);
      solved = true;
    }
  }
  if (!solved) {
    // Taubin (eq. 5–6): with Σω normalised to one, M has eigenvalues m1 = (3k1 + k2)/8,
    // m2 = (k1 + 3k2)/8 for evenly spread directions, inverted by k1 = 3m1 − m2.
    const Mat2 m = taubin / weight_sum;
    VertexCurvature eig;
    principal_from_tensor(m, normal, u, w, eig);
    out.k1 = 3.0 * eig.k1 - eig.k2;
    out.k2 = 3.0 * eig.k2 - eig.k1;
    out.direction1 = eig.direction1;
    out.direction2 = eig.direction2;
  }
  out.kmean = 0.5 * (out.k1 + out.k2);
  out.valid = true;
  return finite(out) ? out : none;
}

VertexCurvature CurvatureEstimator::estimate_at_point(std::span<const Vec3> positions, Index triangle,
                                                      const Vec3& barycentric) const {
  check_positions(positions);
  if (triangle < 0 || static_cast<std::size_t>(triangle) >= triangles_.size())
    throw InputError(fmt::format("curvature estimate: triangle {} out of range (mesh has {} triangles)", triangle,
                                 triangles_.size()));
  Vec3 weights = barycentric.cwiseMax(0.0);
  if (!weights.allFinite() || !(weights.sum() > 0.0))
    throw InputError(fmt::format("curvature estimate: barycentric weights ({} {} {}) have no positive part",
                                 barycentric.x(), barycentric.y(), barycentric.z()));
  weights /= weights.sum();

  const Triangle& t = triangles_[triangle];
  Vec3 normal = Vec3::Zero();
  Mat3 tensor = Mat3::Zero();  // Σ w (k1 d1 d1ᵀ + k2 d2 d2ᵀ)
  double kmean = 0.0, used = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (weights(i) == 0.0) continue;
    const VertexCurvature c = estimate_unchecked(positions, t[i]);
    if (!c.valid) continue;
    normal += weights(i) * c.normal;
    tensor += weights(i) * (c.k1 * c.direction1 * c.direction1.transpose() +
                            c.k2 * c.direction2 * c.direction2.transpose());
    kmean += weights(i) * c.kmean;
    used += weights(i);
  }
  VertexCurvature out;
  if (!(used > 0.0) || !(normal.norm() > 0.0)) return out;
  out.normal = normal.normalized();
  out.kmean = kmean / used;
  Vec3 u, w;
  tangent_basis(out.normal, u, w);
  Mat2 b;
  b << u.dot(tensor * u), u.dot(tensor * w), w.dot(tensor * u), w.dot(tensor * w);
  principal_from_tensor(b / used, out.normal, u, w, out);
  // Projection onto the blended tangent plane can lose a little trace; keep the split
  // but centre it on the blended mean so kmean = (k1 + k2) / 2 holds exactly.
  const double half_split = 0.5 * (out.k1 - out.k2);
  out.k1 = out.kmean + half_split;
  out.k2 = out.kmean - half_split;
  out.valid = true;
  return finite(out) ? out : VertexCurvature{};
}

}  // namespace tactus::mesh
