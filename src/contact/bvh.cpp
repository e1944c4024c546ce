#include "contact/bvh.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {

using detail::BvhNode;

namespace {

/// Boxes are widened by this fraction of the coordinate scale in every query, so rounding
/// in the triangle tests can never report a hit or a distance that the box test pruned.
constexpr double kRelativeMargin = 1e-9;
/// The same for sphere sweeps, whose face test accepts contacts up to 1e-9 barycentric units
/// outside a face (up to about 4e-9 of the coordinate scale away from it).
constexpr double kSweepMargin = 1e-8;
/// Below this depth the build splits by surface-area heuristic; deeper, by the median,
/// which halves the count and so bounds the depth (and the query stacks) by kMaxDepth.
constexpr int kSahMaxDepth = 32;
constexpr int kSahBins = 16;

/// Coordinates must be finite and within ±kMaxCoordinate, so that single-precision boxes
/// can hold them.
constexpr double kMaxCoordinate = 1e30;

bool in_range(std::span<const Vec3> points) {
  if (points.empty()) return true;
  // NaN fails the comparison too.
  return (Eigen::Map<const Eigen::Array<double, 3, Eigen::Dynamic>>(points.data()->data(), 3,
                                                                    static_cast<Eigen::Index>(points.size()))
              .abs() <= kMaxCoordinate)
      .all();
}

double abs_max(const Vec3& v) { return v.cwiseAbs().maxCoeff(); }

double surface_area(const Vec3& lo, const Vec3& hi) {
  const Vec3 e = hi - lo;
  return 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
}

/// max(lo − x, x − hi, 0): how far x lies outside [lo, hi] (maxsd, no branches).
double outside(double lo, double hi, double x) { return std::max(std::max(lo - x, x - hi), 0.0); }

double box_distance2(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = outside(lo[i], hi[i], p[i]);
    d2 += e * e;
  }
  return d2;
}

/// Squared distances from p to both children's boxes of n.
std::array<double, 2> child_distances2(const BvhNode& n, const Vec3& p) {
  std::array<double, 2> d2{0.0, 0.0};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) {
      const double e = outside(n.lo[i][k], n.hi[i][k], p[i]);
      d2[static_cast<std::size_t>(k)] += e * e;
    }
  return d2;
}

/// Squared distance from p to the box of triangle (a, b, c): a cheap lower bound that
/// spares most exact closest-point computations in a leaf.
double triangle_box_distance2(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = outside(std::min({a[i], b[i], c[i]}), std::max({a[i], b[i], c[i]}), p[i]);
    d2 += e * e;
  }
  return d2;
}

Vec3 child_lo(const BvhNode& n, int k) { return {n.lo[0][k], n.lo[1][k], n.lo[2][k]}; }
Vec3 child_hi(const BvhNode& n, int k) { return {n.hi[0][k], n.hi[1][k], n.hi[2][k]}; }

/// Stores an exact (double) box as child k of n in single precision, grown so that it still
/// holds every point: x − |x|·2⁻²² − 10⁻³⁰ rounds to a float below x (a float's rounding
/// error is at most |x|·2⁻²⁴), and likewise above for the upper corner. Cheaper than
/// stepping each coordinate with std::nextafter, which refits would do for every leaf.
void store_box(BvhNode& n, int k, const Vec3& lo, const Vec3& hi) {
  constexpr double kRelative = 0x1p-22, kAbsolute = 1e-30;
  for (int a = 0; a < 3; ++a) {
    n.lo[a][k] = static_cast<float>(lo[a] - std::abs(lo[a]) * kRelative - kAbsolute);
    n.hi[a][k] = static_cast<float>(hi[a] + std::abs(hi[a]) * kRelative + kAbsolute);
  }
}

Vec3 unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

/// A ray (or segment) against boxes widened by `margin`, for 0 ≤ t ≤ t_max.
struct SlabRay {
  Vec3 origin;
  Vec3 inverse_direction;
  double t_max;
  double margin;

  SlabRay(const Vec3& o, const Vec3& d, double max_t, double widen) : origin(o), t_max(max_t), margin(widen) {
    for (int i = 0; i < 3; ++i) inverse_direction[i] = d[i] != 0.0 ? 1.0 / d[i] : kInf;
  }

  [[nodiscard]] bool meets(const BvhNode& n, int k) const { return meets(child_lo(n, k), child_hi(n, k)); }

  [[nodiscard]] bool meets(const Vec3& lo, const Vec3& hi) const { return entry(lo, hi, t_max) != kInf; }

  /// When the ray enters the widened box within [0, until]; +inf when it misses.
  [[nodiscard]] double entry(const Vec3& lo, const Vec3& hi, double until) const {
    double t0 = 0.0, t1 = until;
    for (int i = 0; i < 3; ++i) {
      double a = (lo[i] - margin - origin[i]) * inverse_direction[i];
      double b = (hi[i] + margin - origin[i]) * inverse_direction[i];
      if (a > b) std::swap(a, b);
      // 0 · ∞ (a zero direction component with the origin on a slab plane) is NaN: the
      // comparisons then keep the bound, which errs on the side of visiting the box.
      t0 = a > t0 ? a : t0;
      t1 = b < t1 ? b : t1;
    }
    return t0 <= t1 ? t0 : kInf;
  }
};

// ---- Watertight ray–triangle test (Woop, Benthin & Wald 2013) ----------------------------
//
// The ray is sheared so that it runs along +z through the origin of the (x, y) plane; each
// vertex is transformed on its own, so triangles sharing a vertex see it at the same place.
// Each edge function is computed from its lower-index vertex first, so the two triangles
// sharing an edge get exactly opposite values. An edge function of exactly zero (the ray
// through an edge or a vertex) is decided as if the ray were moved by an infinitesimal
// (ε, ε²) in the sheared plane: the same decision for every triangle, which is what keeps
// crossings of a closed surface counted once.

struct ShearedRay {
  Vec3 origin;
  int kx = 0, ky = 1, kz = 2;
  double sx = 0.0, sy = 0.0, sz = 1.0;

  ShearedRay(const Vec3& o, const Vec3& d) : origin(o) {
    d.cwiseAbs().maxCoeff(&kz);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0) std::swap(kx, ky);  // keep the handedness of the frame
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0 / d[kz];
  }
};

struct Sheared {
  double x, y, z;
};

Sheared shear(const ShearedRay& r, const Vec3& v) {
  const Vec3 a = v - r.origin;
  return {a[r.kx] - r.sx * a[r.kz], a[r.ky] - r.sy * a[r.kz], r.sz * a[r.kz]};
}

/// Twice the signed area of (ray, p, q): positive when the ray passes left of p → q.
double edge_function(const Sheared& p, std::int32_t ip, const Sheared& q, std::int32_t iq) {
  if (ip <= iq) return p.x * q.y - p.y * q.x;
  return -(q.x * p.y - q.y * p.x);
}

/// Whether the ray, moved by (ε, ε²), falls on the inner side of the edge p → q of a
/// triangle whose other edge functions have sign `sign`.
bool owns_zero_edge(const Sheared& p, const Sheared& q, double sign) {
  const double dx = q.x - p.x, dy = q.y - p.y;
  return sign * dy < 0.0 || (dy == 0.0 && sign * dx > 0.0);
}

struct Crossing {
  bool hit = false;
  bool exact_edge = false;  ///< decided by the zero-edge rule, or the triangle is edge-on
  double t = 0.0;
  Vec3 barycentric = Vec3::Zero();
};

/// `ids` are the caller's vertex indices of the corners: they fix the order in which each
/// edge function is computed.
Crossing cross_triangle(const ShearedRay& ray, const Vec3& pa, const Vec3& pb, const Vec3& pc, const mesh::Triangle& ids,
                        double max_t) {
  const Sheared a = shear(ray, pa), b = shear(ray, pb), c = shear(ray, pc);
  const double ea = edge_function(b, ids[1], c, ids[2]);
  const double eb = edge_function(c, ids[2], a, ids[0]);
  const double ec = edge_function(a, ids[0], b, ids[1]);
  const bool negative = ea < 0.0 || eb < 0.0 || ec < 0.0;
  const bool positive = ea > 0.0 || eb > 0.0 || ec > 0.0;
  if (negative && positive) return {};
  Crossing out;
  if (!negative && !positive) {
    // Edge-on triangle whose plane holds the ray: never hit (a moved ray misses it).
    out.exact_edge = true;
    return out;
  }
  const double det = ea + eb + ec;
  const double t = (ea * a.z + eb * b.z + ec * c.z) / det;
  if (!(t >= 0.0 && t <= max_t)) return out;
  const double sign = positive ? 1.0 : -1.0;
  out.exact_edge = ea == 0.0 || eb == 0.0 || ec == 0.0;
  if (out.exact_edge && ((ea == 0.0 && !owns_zero_edge(b, c, sign)) || (eb == 0.0 && !owns_zero_edge(c, a, sign)) ||
                         (ec == 0.0 && !owns_zero_edge(a, b, sign))))
    return out;
  out.hit = true;
  out.t = t;
  out.barycentric = Vec3(ea, eb, ec) / det;
  return out;
}

RayHit make_hit(const Crossing& c, std::int32_t triangle, const Vec3& direction, const Vec3& a, const Vec3& b,
                const Vec3& cc) {
  RayHit h;
  h.t = c.t;
  h.triangle = triangle;
  h.barycentric = c.barycentric;
  h.point = c.barycentric[0] * a + c.barycentric[1] * b + c.barycentric[2] * cc;
  h.normal = unit_normal(a, b, cc);
  h.entering = direction.dot(h.normal) < 0.0;
  return h;
}

void sort_hits(std::vector<RayHit>& hits) {
  std::sort(hits.begin(), hits.end(), [](const RayHit& l, const RayHit& r) {
    return l.t < r.t || (l.t == r.t && l.triangle < r.triangle);
  });
}

void check_ray(const Vec3& origin, const Vec3& direction, double max_t, const char* what) {
  if (!origin.allFinite()) throw InputError(fmt::format("{}: the origin must be finite", what));
  if (!direction.allFinite() || direction.squaredNorm() == 0.0)
    throw InputError(fmt::format("{}: the direction must be finite and non-zero", what));
  if (!(max_t >= 0.0)) throw InputError(fmt::format("{}: max_t must be >= 0, got {}", what, max_t));
}

void check_radius(double r, const char* what) {
  if (!(r >= 0.0)) throw InputError(fmt::format("{}: the radius must be >= 0, got {}", what, r));
}

/// Fixed, non-axis, irrational-looking directions for the inside test.
const Vec3 kParityDirection = Vec3(0.31415926535, 0.57721566490, 0.75384061248).normalized();
const Vec3 kFallbackDirection = Vec3(-0.66180339887, 0.41421356237, -0.62360679775).normalized();

/// Builds the topology of a flat tree top-down over items with centroids and boxes.
class TopDownBuilder {
 public:
  TopDownBuilder(std::span<const Vec3> centroids, std::span<const Aabb> boxes, detail::BvhTopology& tree, int max_leaf,
                 bool use_sah)
      : centroids_(centroids), boxes_(boxes), tree_(tree), max_leaf_(max_leaf), use_sah_(use_sah) {}

  void build() {
    tree_.nodes.clear();
    tree_.leaves.clear();
    tree_.depth = 0;
    tree_.root = 0;
    tree_.root_count = 0;
    if (tree_.order.empty()) return;
    tree_.nodes.reserve(tree_.order.size());  // a binary tree has fewer inner nodes than leaves
    tree_.leaves.reserve(tree_.order.size());
    tree_.root = make(0, static_cast<std::int32_t>(tree_.order.size()), 1, -1, 0, tree_.root_count);
  }

 private:
  /// The child reference for the slots [begin, end), child `side` of inner node `parent`;
  /// count gets a leaf's size (0 otherwise).
  std::int32_t make(std::int32_t begin, std::int32_t end, int level, std::int32_t parent, std::uint8_t side,
                    std::uint8_t& count) {
    tree_.depth = std::max(tree_.depth, level);
    if (end - begin <= max_leaf_) {
      count = static_cast<std::uint8_t>(end - begin);
      tree_.leaves.push_back({begin, parent, count, side});
      return -begin - 1;
    }
    Aabb centroid_box;
    for (std::int32_t s = begin; s < end; ++s) centroid_box.add(centroids_[item(s)]);
    std::int32_t mid = -1;
    if (use_sah_ && level <= kSahMaxDepth) mid = sah_split(begin, end, centroid_box);
    if (mid <= begin || mid >= end) mid = median_split(begin, end, centroid_box);
    const std::size_t index = tree_.nodes.size();
    tree_.nodes.emplace_back();
    const auto self = static_cast<std::int32_t>(index);
    std::uint8_t left_count = 0, right_count = 0;
    const std::int32_t left = make(begin, mid, level + 1, self, 0, left_count);
    const std::int32_t right = make(mid, end, level + 1, self, 1, right_count);
    BvhNode& n = tree_.nodes[index];
    n.child[0] = left;
    n.child[1] = right;
    n.count[0] = left_count;
    n.count[1] = right_count;
    count = 0;
    return static_cast<std::int32_t>(index);
  }

  [[nodiscard]] std::size_t item(std::int32_t s) const {
    return static_cast<std::size_t>(tree_.order[static_cast<std::size_t>(s)]);
  }

  /// Binned surface-area heuristic over the three axes; returns the split slot, or −1.
  std::int32_t sah_split(std::int32_t begin, std::int32_t end, const Aabb& centroid_box) {
    const Vec3 extent = centroid_box.max - centroid_box.min;
    double best_cost = kInf;
    int best_axis = -1, best_bin = -1;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0)) continue;
      std::array<Aabb, kSahBins> bin_box{};
      std::array<std::int32_t, kSahBins> bin_count{};
      const double scale = kSahBins / extent[axis];
      for (std::int32_t s = begin; s < end; ++s) {
        const auto b = static_cast<std::size_t>(bin_of(centroids_[item(s)][axis], centroid_box.min[axis], scale));
        ++bin_count[b];
        bin_box[b].add(boxes_[item(s)].min);
        bin_box[b].add(boxes_[item(s)].max);
      }
      // Sweep from the right for the suffix areas, then from the left for the cost.
      std::array<double, kSahBins> right_area{};
      std::array<std::int32_t, kSahBins> right_count{};
      Aabb acc;
      std::int32_t n = 0;
      for (std::size_t b = kSahBins - 1; b > 0; --b) {
        acc.add(bin_box[b].min);
        acc.add(bin_box[b].max);
        n += bin_count[b];
        right_area[b] = area(acc);
        right_count[b] = n;
      }
      acc = Aabb{};
      n = 0;
      for (std::size_t b = 0; b + 1 < kSahBins; ++b) {
        acc.add(bin_box[b].min);
        acc.add(bin_box[b].max);
        n += bin_count[b];
        if (n == 0 || right_count[b + 1] == 0) continue;
        const double cost = area(acc) * n + right_area[b + 1] * right_count[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = static_cast<int>(b);
        }
      }
    }
    if (best_axis < 0) return -1;
    const double lo = centroid_box.min[best_axis], scale = kSahBins / extent[best_axis];
    auto* first = tree_.order.data() + begin;
    auto* split = std::partition(first, tree_.order.data() + end, [&](std::int32_t i) {
      return bin_of(centroids_[static_cast<std::size_t>(i)][best_axis], lo, scale) <= best_bin;
    });
    return begin + static_cast<std::int32_t>(split - first);
  }

  /// Halves the range at the median centroid along the widest axis (ties by index).
  std::int32_t median_split(std::int32_t begin, std::int32_t end, const Aabb& centroid_box) {
    int axis = 0;
    (centroid_box.max - centroid_box.min).maxCoeff(&axis);
    const std::int32_t mid = begin + (end - begin) / 2;
    std::nth_element(tree_.order.data() + begin, tree_.order.data() + mid, tree_.order.data() + end,
                     [&](std::int32_t l, std::int32_t r) {
                       const double cl = centroids_[static_cast<std::size_t>(l)][axis];
                       const double cr = centroids_[static_cast<std::size_t>(r)][axis];
                       return cl < cr || (cl == cr && l < r);
                     });
    return mid;
  }

  static int bin_of(double c, double lo, double scale) {
    return std::clamp(static_cast<int>((c - lo) * scale), 0, kSahBins - 1);
  }

  static double area(const Aabb& b) { return b.empty() ? 0.0 : surface_area(b.min, b.max); }

  std::span<const Vec3> centroids_;
  std::span<const Aabb> boxes_;
  detail::BvhTopology& tree_;
  int max_leaf_;
  bool use_sah_;
};

/// Bottom-up box update. leaf_box(leaf, lo, hi) gives the exact box of the leaf with that
/// index in tree.leaves.
template <class LeafBox>
void refit_tree(detail::BvhTopology& tree, LeafBox&& leaf_box) {
  if (tree.empty()) return;
  // Leaves first, in slot order (their items are stored in that order too), each into its
  // parent's slot for it; then the inner nodes backward: children always follow their
  // parent in the array, so that sweep is bottom-up.
  Vec3 lo, hi;
  for (std::size_t l = 0; l < tree.leaves.size(); ++l) {
    const detail::BvhLeaf& leaf = tree.leaves[l];
    leaf_box(l, lo, hi);
    if (leaf.parent < 0) {
      tree.root_lo = lo;
      tree.root_hi = hi;
      return;  // a root leaf is the whole tree
    }
    store_box(tree.nodes[static_cast<std::size_t>(leaf.parent)], leaf.side, lo, hi);
  }
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    BvhNode& n = tree.nodes[i];
    for (int k = 0; k < 2; ++k) {
      if (n.child[k] < 0) continue;
      const BvhNode& c = tree.nodes[static_cast<std::size_t>(n.child[k])];
      for (int a = 0; a < 3; ++a) {
        n.lo[a][k] = std::min(c.lo[a][0], c.lo[a][1]);
        n.hi[a][k] = std::max(c.hi[a][0], c.hi[a][1]);
      }
    }
  }
  const BvhNode& root = tree.nodes.front();
  for (int a = 0; a < 3; ++a) {
    tree.root_lo[a] = std::min(root.lo[a][0], root.lo[a][1]);
    tree.root_hi[a] = std::max(root.hi[a][0], root.hi[a][1]);
  }
}

/// Surface-area cost of the tree: every child box's area (times its item count for a
/// leaf) over the root's area. Both children's areas at once in single precision (a
/// rebuild heuristic needs no more), one sum per side so that the two chains overlap.
double area_cost(const detail::BvhTopology& tree) {
  const double root = tree.empty() ? 0.0 : surface_area(tree.root_lo, tree.root_hi);
  if (!(root > 0.0)) return 0.0;
  double sum[2] = {0.0, 0.0};
  for (const BvhNode& n : tree.nodes) {
    float e[3][2];
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 2; ++k) e[a][k] = n.hi[a][k] - n.lo[a][k];
    for (int k = 0; k < 2; ++k)
      sum[k] += static_cast<double>(2.0f * (e[0][k] * e[1][k] + e[1][k] * e[2][k] + e[2][k] * e[0][k]) *
                                    static_cast<float>(std::max<int>(n.count[k], 1)));
  }
  return (sum[0] + sum[1]) / root;
}

double abs_max_of(const detail::BvhTopology& tree) {
  return tree.empty() ? 0.0 : std::max(abs_max(tree.root_lo), abs_max(tree.root_hi));
}

/// Depth-first traversal stack: child references with their leaf sizes and a key.
struct StackEntry {
  std::int32_t ref;
  std::uint8_t count;
  double d2;
};

}  // namespace

// ---- TriangleBvh --------------------------------------------------------------------------

void TriangleBvh::build(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles) {
  if (triangles.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw InputError(fmt::format("triangle BVH: too many triangles ({})", triangles.size()));
  if (positions.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError(fmt::format("triangle BVH: too many vertices ({})", positions.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const mesh::Index v : triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= positions.size())
        throw InputError(fmt::format("triangle BVH: triangle {} refers to vertex {}, but there are {} vertices", t, v,
                                     positions.size()));
  if (!in_range(positions))
    throw InputError(fmt::format("triangle BVH: a vertex position is not finite or beyond ±{:g}", kMaxCoordinate));

  vertex_count_ = positions.size();
  triangles_.assign(triangles.begin(), triangles.end());
  std::vector<Vec3> centroids(triangles.size());
  std::vector<Aabb> boxes(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (const mesh::Index v : triangles[t]) boxes[t].add(positions[static_cast<std::size_t>(v)]);
    centroids[t] = boxes[t].center();
  }
  tree_.order.resize(triangles.size());
  std::iota(tree_.order.begin(), tree_.order.end(), 0);
  TopDownBuilder(centroids, boxes, tree_, kMaxLeafTriangles, true).build();
  if (tree_.depth > kMaxDepth) throw std::logic_error("triangle BVH: depth bound exceeded");

  // Number the vertices in the order the leaves first use them.
  std::vector<std::int32_t> tree_vertex(positions.size(), -1);
  vertex_source_.clear();
  slots_.resize(tree_.order.size());
  for (std::size_t s = 0; s < tree_.order.size(); ++s) {
    slots_[s].triangle = tree_.order[s];
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(triangles_[static_cast<std::size_t>(tree_.order[s])][k]);
      if (tree_vertex[v] < 0) {
        tree_vertex[v] = static_cast<std::int32_t>(vertex_source_.size());
        vertex_source_.push_back(static_cast<std::int32_t>(v));
      }
      slots_[s].corners[k] = tree_vertex[v];
    }
  }
  slot_of_.resize(tree_.order.size());
  for (std::size_t s = 0; s < tree_.order.size(); ++s)
    slot_of_[static_cast<std::size_t>(tree_.order[s])] = static_cast<std::int32_t>(s);
  // Each leaf's distinct corners (about half of its up to 12), for the refit's leaf boxes.
  leaf_vertices_.clear();
  leaf_vertex_first_.assign(1, 0);
  for (const detail::BvhLeaf& leaf : tree_.leaves) {
    const auto begin = leaf_vertices_.size();
    for (std::int32_t s = leaf.first; s < leaf.first + leaf.count; ++s)
      for (const mesh::Index v : slots_[static_cast<std::size_t>(s)].corners)
        if (std::find(leaf_vertices_.begin() + static_cast<std::ptrdiff_t>(begin), leaf_vertices_.end(), v) ==
            leaf_vertices_.end())
          leaf_vertices_.push_back(v);
    leaf_vertex_first_.push_back(static_cast<std::int32_t>(leaf_vertices_.size()));
  }
  positions_.resize(vertex_source_.size());
  for (std::size_t i = 0; i < vertex_source_.size(); ++i)
    positions_[i] = positions[static_cast<std::size_t>(vertex_source_[i])];
  build_cost_ = update_boxes();
  quality_ = 1.0;
}

void TriangleBvh::refit(std::span<const Vec3> positions) {
  if (positions.size() != vertex_count_)
    throw InputError(fmt::format("triangle BVH refit: {} positions given for a tree built over {} vertices",
                                 positions.size(), vertex_count_));
  if (!in_range(positions))
    throw InputError(
        fmt::format("triangle BVH refit: a vertex position is not finite or beyond ±{:g}", kMaxCoordinate));
  for (std::size_t i = 0; i < vertex_source_.size(); ++i)
    positions_[i] = positions[static_cast<std::size_t>(vertex_source_[i])];
  const double cost = update_boxes();
  quality_ = build_cost_ > 0.0 && cost > 0.0 ? cost / build_cost_ : 1.0;
}

double TriangleBvh::update_boxes() {
  refit_tree(tree_, [&](std::size_t leaf, Vec3& lo, Vec3& hi) {
    const std::int32_t* v = leaf_vertices_.data() + leaf_vertex_first_[leaf];
    const std::int32_t* end = leaf_vertices_.data() + leaf_vertex_first_[leaf + 1];
    lo = hi = positions_[static_cast<std::size_t>(*v)];
    for (++v; v != end; ++v) {
      lo = lo.cwiseMin(positions_[static_cast<std::size_t>(*v)]);
      hi = hi.cwiseMax(positions_[static_cast<std::size_t>(*v)]);
    }
  });
  abs_max_ = abs_max_of(tree_);
  return area_cost(tree_);
}

double TriangleBvh::margin(const Vec3& query) const { return kRelativeMargin * (abs_max_ + abs_max(query)); }

Aabb TriangleBvh::bounds() const {
  Aabb b;
  if (!tree_.empty()) {
    b.add(tree_.root_lo);
    b.add(tree_.root_hi);
  }
  return b;
}

/// Nearest-child-first descent over the triangles whose boxes are within a squared distance
/// of p: bound2() is read at every step, so a visit that shrinks it prunes what is left, and
/// visit(slot, a, b, c) gets every triangle whose own box is within it.
template <class Bound, class Visit>
void TriangleBvh::visit_near(const Vec3& p, Bound&& bound2, Visit&& visit) const {
  if (tree_.empty()) return;
  std::array<StackEntry, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = {tree_.root, tree_.root_count, box_distance2(tree_.root_lo, tree_.root_hi, p)};
  while (top > 0) {
    const StackEntry e = stack[--top];
    if (e.d2 > bound2()) continue;
    if (e.ref < 0) {
      const auto first = static_cast<std::size_t>(-e.ref - 1);
      for (std::size_t s = first; s < first + e.count; ++s) {
        const mesh::Triangle& tri = slots_[s].corners;
        const Vec3& a = positions_[static_cast<std::size_t>(tri[0])];
        const Vec3& b = positions_[static_cast<std::size_t>(tri[1])];
        const Vec3& c = positions_[static_cast<std::size_t>(tri[2])];
        if (triangle_box_distance2(a, b, c, p) > bound2()) continue;
        visit(s, a, b, c);
      }
      continue;
    }
    const BvhNode& n = tree_.nodes[static_cast<std::size_t>(e.ref)];
    const auto [d0, d1] = child_distances2(n, p);
    // Push the farther child first so that the nearer one is searched first.
    const int nearer = d0 <= d1 ? 0 : 1;
    const StackEntry near_entry{n.child[nearer], n.count[nearer], nearer == 0 ? d0 : d1};
    const StackEntry far_entry{n.child[1 - nearer], n.count[1 - nearer], nearer == 0 ? d1 : d0};
    if (far_entry.d2 <= bound2()) stack[top++] = far_entry;
    if (near_entry.d2 <= bound2()) stack[top++] = near_entry;
  }
}

SurfacePoint TriangleBvh::closest_point(const Vec3& p, double max_distance) const {
  if (!p.allFinite()) throw InputError("triangle BVH closest point: the query point must be finite");
  if (!(max_distance >= 0.0))
    throw InputError(fmt::format("triangle BVH closest point: max_distance must be >= 0, got {}", max_distance));
  SurfacePoint best;
  const double slack = margin(p);
  const double max_d2 = max_distance * max_distance;
  auto prune_bound = [&](double distance) { return (distance + slack) * (distance + slack); };
  double bound2 = prune_bound(max_distance);
  double best_d2 = kInf;
  std::int32_t best_t = -1;
  std::size_t best_slot = 0;
  TrianglePoint best_q;
  visit_near(
      p, [&] { return bound2; },
      [&](std::size_t s, const Vec3& a, const Vec3& b, const Vec3& c) {
        const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
        const double d2 = (p - q.point).squaredNorm();
        const std::int32_t t = slots_[s].triangle;
        if (d2 <= max_d2 && (d2 < best_d2 || (d2 == best_d2 && t < best_t))) {
          best_d2 = d2;
          best_t = t;
          best_slot = s;
          best_q = q;
          bound2 = std::min(bound2, prune_bound(std::sqrt(d2)));
        }
      });
  if (best_t < 0) return best;
  const mesh::Triangle& tri = slots_[best_slot].corners;
  best.triangle = best_t;
  best.point = best_q.point;
  best.barycentric = best_q.barycentric;
  best.normal = unit_normal(positions_[static_cast<std::size_t>(tri[0])], positions_[static_cast<std::size_t>(tri[1])],
                            positions_[static_cast<std::size_t>(tri[2])]);
  best.distance = std::sqrt(best_d2);
  return best;
}

std::optional<std::array<Vec3, 3>> TriangleBvh::triangle_corners(std::int32_t t) const {
  if (t < 0 || static_cast<std::size_t>(t) >= slot_of_.size()) return std::nullopt;
  const mesh::Triangle& tri = slots_[static_cast<std::size_t>(slot_of_[static_cast<std::size_t>(t)])].corners;
  return std::array<Vec3, 3>{positions_[static_cast<std::size_t>(tri[0])], positions_[static_cast<std::size_t>(tri[1])],
                             positions_[static_cast<std::size_t>(tri[2])]};
}

template <class Visit>
void TriangleBvh::visit_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
  if (tree_.empty()) return;
  const auto overlaps = [&](const Vec3& node_lo, const Vec3& node_hi) {
    return (node_lo.array() <= hi.array()).all() && (lo.array() <= node_hi.array()).all();
  };
  if (!overlaps(tree_.root_lo, tree_.root_hi)) return;
  std::array<StackEntry, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = {tree_.root, tree_.root_count, 0.0};
  while (top > 0) {
    const StackEntry e = stack[--top];
    if (e.ref < 0) {
      const auto first = static_cast<std::size_t>(-e.ref - 1);
      for (std::size_t s = first; s < first + e.count; ++s) visit(s);
      continue;
    }
    const BvhNode& n = tree_.nodes[static_cast<std::size_t>(e.ref)];
    for (int k = 1; k >= 0; --k)
      if (overlaps(child_lo(n, k), child_hi(n, k))) stack[top++] = {n.child[k], n.count[k], 0.0};
  }
}

ClosestSurfacePoint TriangleBvh::closest_point_with_side(const Vec3& p) const {
  if (!p.allFinite()) throw InputError("triangle BVH closest point: the query point must be finite");
  const PseudoNormalSum side(p, closest_point(p));
  Vec3 sum = Vec3::Zero();
  if (side.on_edge_or_vertex() && !tree_.empty()) {
    // Summed in ascending triangle index, as the brute-force scan does, so that both give
    // the same bits (an edge has two triangles, a vertex its valence; more than fit here
    // are summed in tree order, equal up to rounding).
    struct Term {
      std::int32_t triangle;
      Vec3 value;
    };
    std::array<Term, 32> terms;
    std::size_t count = 0;
    Vec3 overflow = Vec3::Zero();
    visit_box(side.lo(), side.hi(), [&](std::size_t s) {
      const mesh::Triangle& tri = slots_[s].corners;
      const Vec3 term = side.term(positions_[static_cast<std::size_t>(tri[0])],
                                  positions_[static_cast<std::size_t>(tri[1])],
                                  positions_[static_cast<std::size_t>(tri[2])]);
      if (term == Vec3::Zero()) return;
      if (count < terms.size())
        terms[count++] = {slots_[s].triangle, term};
      else
        overflow += term;
    });
    std::sort(terms.begin(), terms.begin() + static_cast<std::ptrdiff_t>(count),
              [](const Term& l, const Term& r) { return l.triangle < r.triangle; });
    for (std::size_t i = 0; i < count; ++i) sum += terms[i].value;
    sum += overflow;
  }
  return side.result(sum);
}

SweepHit TriangleBvh::sweep_sphere(const Vec3& from, const Vec3& to, double radius) const {
  if (!from.allFinite() || !to.allFinite()) throw InputError("triangle BVH sphere sweep: the end points must be finite");
  check_radius(radius, "triangle BVH sphere sweep");
  SweepHit best;
  if (tree_.empty()) return best;
  const Vec3 d = to - from;
  // The brute-force scan's reject box, applied per triangle here too, so that both test the
  // same triangles with the same function.
  const Vec3 lo = from.cwiseMin(to).array() - radius, hi = from.cwiseMax(to).array() + radius;
  // Node boxes grow by the radius and a margin above the face test's tolerance (a contact
  // up to 1e-9 barycentric units outside a face) and rounding.
  const double grow = radius + kSweepMargin * (abs_max_ + std::max(abs_max(from), abs_max(to)) + radius);
  // Entry time of the centre into a grown box.
  const SlabRay centre(from, d, 1.0, grow);
  const auto entry = [&](const Vec3& box_lo, const Vec3& box_hi, double until) {
    return centre.entry(box_lo, box_hi, until);
  };
  const double root_entry = entry(tree_.root_lo, tree_.root_hi, 1.0);
  if (!(root_entry <= 1.0)) return best;
  std::array<StackEntry, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = {tree_.root, tree_.root_count, root_entry};
  while (top > 0) {
    const StackEntry e = stack[--top];
    const double t_max = best.hit ? best.time : 1.0;
    if (e.d2 > t_max) continue;  // a contact at the same time may still win by index
    if (e.ref < 0) {
      const auto first = static_cast<std::size_t>(-e.ref - 1);
      for (std::size_t s = first; s < first + e.count; ++s) {
        const mesh::Triangle& tri = slots_[s].corners;
        const Vec3& a = positions_[static_cast<std::size_t>(tri[0])];
        const Vec3& b = positions_[static_cast<std::size_t>(tri[1])];
        const Vec3& c = positions_[static_cast<std::size_t>(tri[2])];
        if (!((a.cwiseMin(b).cwiseMin(c).array() <= hi.array()).all() &&
              (lo.array() <= a.cwiseMax(b).cwiseMax(c).array()).all()))
          continue;
        const SweepHit h = sweep_sphere_triangle(from, to, radius, a, b, c);
        const std::int32_t t = slots_[s].triangle;
        if (h.hit && (!best.hit || h.time < best.time || (h.time == best.time && t < best.triangle))) {
          best = h;
          best.triangle = t;
        }
      }
      continue;
    }
    const BvhNode& n = tree_.nodes[static_cast<std::size_t>(e.ref)];
    const double t0 = entry(child_lo(n, 0), child_hi(n, 0), t_max);
    const double t1 = entry(child_lo(n, 1), child_hi(n, 1), t_max);
    // The later entry is pushed first, so that the earlier one is searched first.
    const int earlier = t0 <= t1 ? 0 : 1;
    const double t_earlier = earlier == 0 ? t0 : t1, t_later = earlier == 0 ? t1 : t0;
    if (t_later <= t_max) stack[top++] = {n.child[1 - earlier], n.count[1 - earlier], t_later};
    if (t_earlier <= t_max) stack[top++] = {n.child[earlier], n.count[earlier], t_earlier};
  }
  return best;
}

template <class Visit>
void TriangleBvh::visit_ray(const Vec3& origin, const Vec3& direction, double max_t, Visit&& visit) const {
  if (tree_.empty()) return;
  const SlabRay slab(origin, direction, max_t, margin(origin));
  if (!slab.meets(tree_.root_lo, tree_.root_hi)) return;
  std::array<StackEntry, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = {tree_.root, tree_.root_count, 0.0};
  while (top > 0) {
    const StackEntry e = stack[--top];
    if (e.ref < 0) {
      const auto first = static_cast<std::size_t>(-e.ref - 1);
      for (std::size_t s = first; s < first + e.count; ++s) visit(s);
      continue;
    }
    const BvhNode& n = tree_.nodes[static_cast<std::size_t>(e.ref)];
    for (int k = 1; k >= 0; --k)
      if (slab.meets(n, k)) stack[top++] = {n.child[k], n.count[k], 0.0};
  }
}

void TriangleBvh::raycast(const Vec3& origin, const Vec3& direction, double max_t, std::vector<RayHit>& hits) const {
  check_ray(origin, direction, max_t, "triangle BVH raycast");
  hits.clear();
  const ShearedRay ray(origin, direction);
  visit_ray(origin, direction, max_t, [&](std::size_t s) {
    const mesh::Triangle& tri = slots_[s].corners;
    const Vec3& a = positions_[static_cast<std::size_t>(tri[0])];
    const Vec3& b = positions_[static_cast<std::size_t>(tri[1])];
    const Vec3& c = positions_[static_cast<std::size_t>(tri[2])];
    const mesh::Triangle ids = {vertex_source_[static_cast<std::size_t>(tri[0])],
                                vertex_source_[static_cast<std::size_t>(tri[1])],
                                vertex_source_[static_cast<std::size_t>(tri[2])]};
    const Crossing crossing = cross_triangle(ray, a, b, c, ids, max_t);
    if (crossing.hit) hits.push_back(make_hit(crossing, slots_[s].triangle, direction, a, b, c));
  });
  sort_hits(hits);
}

void TriangleBvh::segment(const Vec3& a, const Vec3& b, std::vector<RayHit>& hits) const {
  if (!a.allFinite() || !b.allFinite()) throw InputError("triangle BVH segment: the end points must be finite");
  if (a == b) {
    hits.clear();
    return;
  }
  raycast(a, b - a, 1.0, hits);
}

void TriangleBvh::sphere_overlap(const Vec3& center, double radius, std::vector<std::int32_t>& triangles) const {
  if (!center.allFinite()) throw InputError("triangle BVH sphere overlap: the centre must be finite");
  check_radius(radius, "triangle BVH sphere overlap");
  triangles.clear();
  const double r2 = radius * radius;
  const double reach = radius + margin(center);
  const double bound2 = reach * reach;
  visit_near(
      center, [&] { return bound2; },
      [&](std::size_t s, const Vec3& a, const Vec3& b, const Vec3& c) {
        const TrianglePoint q = closest_point_on_triangle(center, a, b, c);
        if ((center - q.point).squaredNorm() <= r2) triangles.push_back(slots_[s].triangle);
      });
  std::sort(triangles.begin(), triangles.end());
}

int TriangleBvh::crossing_parity(const Vec3& p, const Vec3& direction, bool& degenerate) const {
  const ShearedRay ray(p, direction);
  int parity = 0;
  visit_ray(p, direction, kInf, [&](std::size_t s) {
    const mesh::Triangle& tri = slots_[s].corners;
    const mesh::Triangle ids = {vertex_source_[static_cast<std::size_t>(tri[0])],
                                vertex_source_[static_cast<std::size_t>(tri[1])],
                                vertex_source_[static_cast<std::size_t>(tri[2])]};
    const Crossing c = cross_triangle(ray, positions_[static_cast<std::size_t>(tri[0])],
                                      positions_[static_cast<std::size_t>(tri[1])],
                                      positions_[static_cast<std::size_t>(tri[2])], ids, kInf);
    parity ^= c.hit ? 1 : 0;
    degenerate = degenerate || c.exact_edge;
  });
  return parity;
}

bool TriangleBvh::inside(const Vec3& p) const {
  if (!p.allFinite()) throw InputError("triangle BVH inside test: the query point must be finite");
  if (tree_.empty()) return false;
  bool degenerate = false;
  const int parity = crossing_parity(p, kParityDirection, degenerate);
  if (!degenerate) return parity == 1;
  // The tie rule already counts exact edge and vertex crossings once; a second ray that
  // meets no such case confirms it without relying on the rule.
  bool degenerate_again = false;
  const int second = crossing_parity(p, kFallbackDirection, degenerate_again);
  return (degenerate_again ? parity : second) == 1;
}

void raycast_surface(const Vec3& origin, const Vec3& direction, double max_t, std::span<const Vec3> positions,
                     std::span<const mesh::Triangle> triangles, std::vector<RayHit>& hits) {
  check_ray(origin, direction, max_t, "surface raycast");
  hits.clear();
  const ShearedRay ray(origin, direction);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const mesh::Triangle& tri = triangles[t];
    const Vec3& a = positions[static_cast<std::size_t>(tri[0])];
    const Vec3& b = positions[static_cast<std::size_t>(tri[1])];
    const Vec3& c = positions[static_cast<std::size_t>(tri[2])];
    const Crossing crossing = cross_triangle(ray, a, b, c, tri, max_t);
    if (crossing.hit) hits.push_back(make_hit(crossing, static_cast<std::int32_t>(t), direction, a, b, c));
  }
  sort_hits(hits);
}

// ---- PointTree ----------------------------------------------------------------------------

void PointTree::build(std::span<const Vec3> points) {
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw InputError(fmt::format("point tree: too many points ({})", points.size()));
  if (!in_range(points))
    throw InputError(fmt::format("point tree: a point is not finite or beyond ±{:g}", kMaxCoordinate));
  tree_.order.resize(points.size());
  std::iota(tree_.order.begin(), tree_.order.end(), 0);
  TopDownBuilder(points, {}, tree_, kMaxLeafPoints, false).build();
  if (tree_.depth > kMaxDepth) throw std::logic_error("point tree: depth bound exceeded");
  points_.resize(points.size());
  refit(points);
}

void PointTree::refit(std::span<const Vec3> points) {
  if (points.size() != tree_.order.size())
    throw InputError(fmt::format("point tree refit: {} points given for a tree built over {}", points.size(),
                                 tree_.order.size()));
  if (!in_range(points))
    throw InputError(fmt::format("point tree refit: a point is not finite or beyond ±{:g}", kMaxCoordinate));
  for (std::size_t s = 0; s < tree_.order.size(); ++s) points_[s] = points[static_cast<std::size_t>(tree_.order[s])];
  refit_tree(tree_, [&](std::size_t leaf, Vec3& lo, Vec3& hi) {
    const detail::BvhLeaf& l = tree_.leaves[leaf];
    const Vec3* q = points_.data() + l.first;
    lo = hi = q[0];
    for (std::uint8_t k = 1; k < l.count; ++k) {
      lo = lo.cwiseMin(q[k]);
      hi = hi.cwiseMax(q[k]);
    }
  });
  abs_max_ = abs_max_of(tree_);
}

void PointTree::nodes_near_segment(const Vec3& a, const Vec3& b, double r, std::vector<std::int32_t>& out) const {
  if (!a.allFinite() || !b.allFinite()) throw InputError("point tree: the segment ends must be finite");
  check_radius(r, "point tree: nodes near segment");
  out.clear();
  if (tree_.empty()) return;
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double r2 = r * r;
  // The segment against boxes grown by r: every point within r lies in one of them.
  const SlabRay slab(a, d, 1.0, r + kRelativeMargin * (abs_max_ + std::max(abs_max(a), abs_max(b))));
  if (!slab.meets(tree_.root_lo, tree_.root_hi)) return;
  std::array<StackEntry, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = {tree_.root, tree_.root_count, 0.0};
  while (top > 0) {
    const StackEntry e = stack[--top];
    if (e.ref < 0) {
      const auto first = static_cast<std::size_t>(-e.ref - 1);
      for (std::size_t s = first; s < first + e.count; ++s) {
        const Vec3& p = points_[s];
        const double u = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
        if ((p - (a + u * d)).squaredNorm() <= r2) out.push_back(tree_.order[s]);
      }
      continue;
    }
    const BvhNode& n = tree_.nodes[static_cast<std::size_t>(e.ref)];
    for (int k = 1; k >= 0; --k)
      if (slab.meets(n, k)) stack[top++] = {n.child[k], n.count[k], 0.0};
  }
  std::sort(out.begin(), out.end());
}

void TriangleBvh::node_boxes(int levels, std::vector<std::pair<Vec3, Vec3>>& out) const {
  if (tree_.empty() || levels < 0) return;
  out.emplace_back(tree_.root_lo, tree_.root_hi);
  // Each inner node holds its children's boxes: a child at depth d + 1 is listed from its parent.
  auto descend = [&](auto&& self, std::int32_t ref, int level) -> void {
    if (ref < 0 || level >= levels) return;
    const detail::BvhNode& n = tree_.nodes[static_cast<std::size_t>(ref)];
    for (int c = 0; c < 2; ++c) {
      out.emplace_back(Vec3(n.lo[0][c], n.lo[1][c], n.lo[2][c]), Vec3(n.hi[0][c], n.hi[1][c], n.hi[2][c]));
      self(self, n.child[c], level + 1);
    }
  };
  descend(descend, tree_.root, 0);
}

}  // namespace tactus::contact
