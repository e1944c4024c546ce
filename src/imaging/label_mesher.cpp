// The one translation unit that includes CGAL (Mesh_3 on a labelled image): it alone pays
// CGAL's compile time.
#include "imaging/label_mesher.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/progress.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

namespace tactus::imaging {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;
using FacetCriteria = Criteria::Facet_criteria;
using CellCriteria = Criteria::Cell_criteria;
using Point = Triangulation::Bare_point;
using Index = Domain::Index;

/// Sizes by label (compact index) in mesh units: a cell takes its label's; a facet the finer
/// of its two sides' (the background, index 0, has none).
struct LabelSizes {
  std::vector<double> size;  ///< by compact index; [0] unused
  double operator()(const Point&, const int dimension, const Index& index) const {
    if (dimension == 3) {
      if (const auto* label = boost::get<Domain::Subdomain_index>(&index))
        if (*label > 0 && static_cast<std::size_t>(*label) < size.size()) return size[static_cast<std::size_t>(*label)];
    } else if (dimension == 2) {
      if (const auto* patch = boost::get<Domain::Surface_patch_index>(&index)) {
        double s = 0.0;
        for (int side : {patch->first, patch->second})
          if (side > 0 && static_cast<std::size_t>(side) < size.size())
            s = s == 0.0 ? size[static_cast<std::size_t>(side)] : std::min(s, size[static_cast<std::size_t>(side)]);
        if (s > 0.0) return s;
      }
    }
    return *std::min_element(size.begin() + 1, size.end());
  }
};

/// A CGAL image of bytes over the voxels, in mesh units (the smallest spacing is 1), origin 0.
CGAL::Image_3 byte_image(const std::vector<std::uint8_t>& voxels, const std::array<std::size_t, 3>& size,
                         const Vec3& voxel_units) {
  _image* raw = ::_createImage(size[0], size[1], size[2], 1, voxel_units[0], voxel_units[1], voxel_units[2], 1,
                               WK_FIXED, SGN_UNSIGNED);
  if (!raw) throw std::runtime_error("CGAL: cannot allocate the label image");
  std::memcpy(raw->data, voxels.data(), voxels.size());
  return CGAL::Image_3(raw);
}

/// Puts points on every label's boundary into the triangulation before the refinement:
/// CGAL's default start shoots rays from the image centre and can miss a small or
/// off-centre label altogether. Up to `per_label` crossings each, spread over the image.
void seed_boundaries(Complex& c3t3, const Domain& domain, const std::vector<std::uint8_t>& compact,
                     const std::array<std::size_t, 3>& size, const Vec3& voxel_units, int label_count) {
  constexpr std::size_t per_label = 48;
  // Faces between two voxels of different labels, by label.
  std::vector<std::vector<std::pair<std::size_t, int>>> crossings(static_cast<std::size_t>(label_count));
  const std::array<std::size_t, 3> stride{1, size[0], size[0] * size[1]};
  for (std::size_t k = 0, v = 0; k < size[2]; ++k)
    for (std::size_t j = 0; j < size[1]; ++j)
      for (std::size_t i = 0; i < size[0]; ++i, ++v) {
        const std::array<std::size_t, 3> p{i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (p[a] + 1 >= size[a]) continue;
          const std::uint8_t here = compact[v], there = compact[v + stride[a]];
          if (here == there) continue;
          if (here) crossings[here].push_back({v, a});
          if (there) crossings[there].push_back({v, a});
        }
      }
  auto centre = [&](std::size_t v) {
    const std::size_t i = v % size[0], j = (v / size[0]) % size[1], k = v / stride[2];
    return Point(static_cast<double>(i) * voxel_units[0], static_cast<double>(j) * voxel_units[1],
                 static_cast<double>(k) * voxel_units[2]);
  };
  auto& tr = c3t3.triangulation();
  const auto intersect = domain.construct_intersection_object();
  for (const auto& list : crossings) {
    if (list.empty()) continue;
    const std::size_t step = std::max<std::size_t>(1, list.size() / per_label);
    for (std::size_t n = 0; n < list.size(); n += step) {
      const auto [v, axis] = list[n];
      const Point a = centre(v), b = centre(v + stride[static_cast<std::size_t>(axis)]);
      const auto hit = intersect(Kernel::Segment_3(a, b));
      if (std::get<2>(hit) == 0) continue;
      const auto vertex = tr.insert(Triangulation::Point(std::get<0>(hit)));
      if (vertex == Triangulation::Vertex_handle()) continue;
      c3t3.set_dimension(vertex, 2);
      c3t3.set_index(vertex, std::get<1>(hit));
    }
  }
}

}  // namespace

mesh::TetMesh mesh_label_image(const LabelImage& image, const LabelMeshOptions& options) {
  const SourceLocation at{image.source, {}, {}, {}};
  if (!(options.cell_size > 0.0 && std::isfinite(options.cell_size)))
    throw InputError("--cell-size must be positive");
  const auto counts = count_labels(image);
  if (counts.empty()) throw InputError(at, "the image has no nonzero labels: nothing to mesh");
  if (counts.size() > 255)
    throw InputError(at, fmt::format("{} labels; at most 255 are meshed at once", counts.size()));
  for (const auto& c : counts)
    if (c.voxels < options.min_voxels)
      throw InputError(at, fmt::format("label {} has {} voxel{}; at least {} are needed to mesh it", c.label,
                                       c.voxels, c.voxels == 1 ? "" : "s", options.min_voxels));
  for (const auto& [what, by_label] : {std::pair{"cell size", &options.cell_size_by_label},
                                       std::pair{"facet distance", &options.facet_distance_by_label}})
    for (const auto& entry : *by_label) {
      if (!(entry.second > 0.0 && std::isfinite(entry.second)))
        throw InputError(fmt::format("the {} of label {} must be positive", what, entry.first));
      if (std::none_of(counts.begin(), counts.end(), [&](const LabelVoxels& c) { return c.label == entry.first; }))
        throw InputError(at, fmt::format("a {} is given for label {}, which the image does not hold", what, entry.first));
    }

  // Mesh units: the smallest spacing is 1, so CGAL's tolerances (relative to the image)
  // and its one-unit margin around the image are in voxels, not in metres.
  const double unit = image.spacing.minCoeff();
  const Vec3 voxel_units = image.spacing / unit;
  const int label_count = static_cast<int>(counts.size()) + 1;
  std::unordered_map<std::int32_t, std::uint8_t> compact_of;
  for (std::size_t c = 0; c < counts.size(); ++c) compact_of[counts[c].label] = static_cast<std::uint8_t>(c + 1);
  // One voxel of background around the image: a label that touches the image's edge ends
  // at the outer face of its last voxel, as inside, instead of at that voxel's centre.
  const std::array<std::size_t, 3> padded{image.size[0] + 2, image.size[1] + 2, image.size[2] + 2};
  std::vector<std::uint8_t> compact(padded[0] * padded[1] * padded[2], 0);
  for (std::size_t k = 0; k < image.size[2]; ++k)
    for (std::size_t j = 0; j < image.size[1]; ++j)
      for (std::size_t i = 0; i < image.size[0]; ++i) {
        const std::int32_t label = image.labels[image.index(i, j, k)];
        if (label != 0) compact[(i + 1) + padded[0] * ((j + 1) + padded[1] * (k + 1))] = compact_of.at(label);
      }

  Complex c3t3;
  // CGAL reports nothing while it works, so the bar moves at the end of each phase, by the
  // phase's usual share of the time: weights, seeds, refinement, perturbation, exudation.
  constexpr std::array<std::size_t, 6> kPercentAfterPhase{0, 10, 15, 75, 95, 100};
  std::optional<Progress> progress;
  if (options.progress) progress.emplace("meshing labels", 100);
  auto phase_done = [&](std::size_t phase) {
    if (progress) progress->update(kPercentAfterPhase[phase]);
  };

  CGAL::get_default_random() = CGAL::Random(options.seed);
  CGAL::Random rng(options.seed);
  const CGAL::Image_3 labels_image = byte_image(compact, padded, voxel_units);
  CGAL::Image_3 weights_image;
  if (options.smooth_sigma > 0.0)
    weights_image =
        byte_image(detail::label_weights(compact, padded, voxel_units, label_count, options.smooth_sigma), padded,
                   voxel_units);
  phase_done(1);
  namespace p = CGAL::parameters;
  // The boundary is found by bisection to this fraction of the image's diagonal.
  const double relative_error = 1e-6;
  Domain domain = options.smooth_sigma > 0.0
                      ? Domain::create_labeled_image_mesh_domain(labels_image, p::weights = weights_image,
                                                                  p::relative_error_bound = relative_error,
                                                                  p::p_rng = &rng)
                      : Domain::create_labeled_image_mesh_domain(labels_image, p::relative_error_bound = relative_error,
                                                                  p::p_rng = &rng);

  LabelSizes sizes;
  sizes.size.assign(static_cast<std::size_t>(label_count), options.cell_size / unit);
  for (const auto& entry : options.cell_size_by_label) sizes.size[compact_of.at(entry.first)] = entry.second / unit;
  const double distance = options.facet_distance.value_or(0.5 * unit) / unit;
  if (!(distance > 0.0 && std::isfinite(distance))) throw InputError("--facet-distance must be positive");
  LabelSizes distances;
  distances.size.assign(static_cast<std::size_t>(label_count), distance);
  for (const auto& entry : options.facet_distance_by_label)
    distances.size[compact_of.at(entry.first)] = entry.second / unit;
  const FacetCriteria facets(options.facet_angle_deg, sizes, distances);
  const CellCriteria cells(options.radius_edge_ratio, sizes);
  const Criteria criteria(facets, cells);

  seed_boundaries(c3t3, domain, compact, padded, voxel_units, label_count);
  phase_done(2);
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_perturb(), p::no_exude());
  phase_done(3);
  if (options.optimize) {
    // Time limits only as a ceiling: a mesh that reaches the bound is the same on every machine.
    CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = 120.0, p::sliver_bound = options.sliver_bound_deg);
    phase_done(4);
    CGAL::exude_mesh_3(c3t3, p::time_limit = 120.0, p::sliver_bound = options.sliver_bound_deg);
  }
  phase_done(5);
  if (progress) progress->finish();

  // Output: world metres; a mirrored placement (negative determinant) turns every tet
  // over, so two corners are swapped to keep them positively oriented.
  const Mat3 to_world = image.direction * unit;
  const bool mirrored = image.direction.determinant() < 0.0;
  mesh::TetMesh out;
  std::unordered_map<Triangulation::Vertex_handle, int> vertex_index;
  auto index_of = [&](Triangulation::Vertex_handle v) {
    const auto [it, inserted] = vertex_index.emplace(v, static_cast<int>(out.vertices.size()));
    if (inserted) {
      const auto& q = v->point();
      out.vertices.push_back(image.origin + to_world * (Vec3(q.x(), q.y(), q.z()) - voxel_units));  // unpad
    }
    return it->second;
  };
  std::vector<std::size_t> tets_by_label(static_cast<std::size_t>(label_count), 0);
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    mesh::Tet t{index_of(c->vertex(0)), index_of(c->vertex(1)), index_of(c->vertex(2)), index_of(c->vertex(3))};
    if (mirrored) std::swap(t[2], t[3]);
    out.tets.push_back(t);
    const int label = c3t3.subdomain_index(c);
    out.tet_regions.push_back(counts[static_cast<std::size_t>(label - 1)].label);
    ++tets_by_label[static_cast<std::size_t>(label)];
  }
  for (std::size_t c = 0; c < counts.size(); ++c)
    if (tets_by_label[c + 1] == 0)
      throw InputError(at, fmt::format("label {} ({} voxels) got no tetrahedra at cell size {} m; give it a "
                                       "smaller size (--cell-size-label {}=SIZE)",
                                       counts[c].label, counts[c].voxels, sizes.size[c + 1] * unit, counts[c].label));
  return out;
}

}  // namespace tactus::imaging
