#pragma once
// The labelled-image mesher: every nonzero label of a LabelImage becomes its own region of
// one tetrahedral mesh (CGAL Mesh_3 on the labelled image), the interfaces between labels
// shared by the tetrahedra of both sides.
#include <cstdint>
#include <map>
#include <optional>

#include "imaging/label_image.hpp"
#include "mesh/tet_mesh.hpp"

namespace tactus::imaging {

struct LabelMeshOptions {
  /// Largest tetrahedron circumradius [m] (CGAL's cell_size) and largest surface Delaunay
  /// ball radius of the facets (facet_size) of every label...
  double cell_size = 0.0;
  /// ...and of the labels named here; an interface takes the finer size of its two sides.
  std::map<std::int32_t, double> cell_size_by_label;
  /// Largest distance between a facet and the label boundary [m]; default: half the
  /// smallest voxel spacing...
  std::optional<double> facet_distance;
  /// ...and of the labels named here; an interface takes the finer distance of its two sides.
  std::map<std::int32_t, double> facet_distance_by_label;
  double facet_angle_deg = 25.0;  ///< smallest facet angle (CGAL keeps it below 30°)
  double radius_edge_ratio = 3.0;
  /// Gaussian smoothing of the label boundaries, standard deviation in units of the
  /// smallest voxel spacing (the same length along every axis); 0: none (the boundaries
  /// follow the voxels' trilinear interpolation).
  double smooth_sigma = 0.0;
  /// A label with fewer voxels is refused: too small to mesh at any useful size.
  std::size_t min_voxels = 8;
  bool optimize = true;  ///< sliver perturbation and exudation after the refinement
  /// Their target: the smallest dihedral angle [°]. 5 costs a tenth of the refinement's
  /// time; 8 ten times more.
  double sliver_bound_deg = 5.0;
  bool progress = true;  ///< a progress bar on stderr (see core/progress.hpp)
  std::uint32_t seed = 0;
};

/// The mesh in world metres, tet_regions holding the original labels. Throws InputError
/// (naming the image) for an image without nonzero labels, a label with fewer than
/// min_voxels voxels or one left without tetrahedra at the size asked, more than 255
/// labels, or a size that is not positive.
mesh::TetMesh mesh_label_image(const LabelImage& image, const LabelMeshOptions& options);

namespace detail {
/// Per-voxel weights (0..255) for CGAL's weighted labelled domain: the largest of each
/// label's Gaussian-smoothed indicator (Stalling et al. 1998; CGAL's
/// generate_label_weights does the same with ITK). `compact` holds labels 0..label_count-1;
/// `voxel_units`, the spacing over the smallest spacing; `sigma` in smallest spacings.
std::vector<std::uint8_t> label_weights(const std::vector<std::uint8_t>& compact, const std::array<std::size_t, 3>& size,
                                        const Vec3& voxel_units, int label_count, double sigma);
}  // namespace detail

}  // namespace tactus::imaging
