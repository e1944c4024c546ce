// Real segmentations written by other tools (tests/data/label_images/SOURCES.md): the
// placement read from their headers, and meshes of them.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "imaging/label_mesher.hpp"
#include "mesh/quality.hpp"
#include "phantom.hpp"

namespace tactus::imaging {
namespace {

const std::filesystem::path kDir = std::filesystem::path(TACTUS_TEST_DATA_DIR) / "label_images";

TEST(ExternalLabelMaps, PlacementFromTheHeader) {
  // brain1: LPS directions (0.78125,0,0) (0,-0.78125,0) (0,0,6.5), origin (-99.61,99.61,-78) mm.
  const LabelImage image = read_nrrd(kDir / "pyradiomics_brain1_label.nrrd");
  EXPECT_EQ(image.size, (std::array<std::size_t, 3>{256, 256, 25}));
  EXPECT_TRUE(image.spacing.isApprox(Vec3(0.78125e-3, 0.78125e-3, 6.5e-3), 1e-9)) << image.spacing.transpose();
  EXPECT_TRUE(image.origin.isApprox(Vec3(0.099609375, -0.099609375, -0.078), 1e-9)) << image.origin.transpose();
  EXPECT_TRUE(image.direction.isApprox(Vec3(-1, 1, 1).asDiagonal().toDenseMatrix(), 1e-12)) << image.direction;
  const auto counts = count_labels(image);
  ASSERT_EQ(counts.size(), 1u);
  EXPECT_EQ(counts[0].label, 1);
  EXPECT_EQ(counts[0].voxels, 4137u);
}

/// Meshes `file` and compares each label's meshed volume with its voxels' volume.
void mesh_and_check(const std::string& file, double cell_size, const std::map<int, double>& tolerance) {
  const LabelImage image = read_nrrd(kDir / file);
  LabelMeshOptions o;
  o.cell_size = cell_size;
  o.progress = false;
  const mesh::TetMesh m = mesh_label_image(image, o);
  const auto q = mesh::tet_quality(m);
  EXPECT_EQ(q.inverted, 0u) << file;
  EXPECT_GT(q.min_dihedral_deg.min, 2.0) << file;
  const auto volume = test::region_volumes(m);
  std::set<int> meshed;
  for (const auto& entry : volume) meshed.insert(entry.first);
  for (const auto& c : count_labels(image)) {
    EXPECT_TRUE(meshed.count(c.label)) << file << " label " << c.label;
    const auto it = tolerance.find(c.label);
    if (it == tolerance.end()) continue;
    const double voxels = static_cast<double>(c.voxels) * image.voxel_volume();
    EXPECT_NEAR(volume.at(c.label) / voxels, 1.0, it->second) << file << " label " << c.label;
  }
}

// Tolerances: the meshed boundary is the trilinear 0.5 level, which cuts corners of the
// voxel staircase; on these thick slices (3 to 6.5 mm) and small structures that costs a few
// percent. Labels 1 and 7 of the prostate, one voxel wide, only have to be present.
TEST(ExternalLabelMaps, BrainTumour) { mesh_and_check("pyradiomics_brain1_label.nrrd", 3e-3, {{1, 0.05}}); }
TEST(ExternalLabelMaps, LungNodule) { mesh_and_check("pyradiomics_lung1_label.nrrd", 2e-3, {{1, 0.06}}); }
TEST(ExternalLabelMaps, ProstatePhantomFourLabels) {
  mesh_and_check("pyradiomics_prostate_phantom_subvolume-label.nrrd", 3e-3, {{8, 0.2}, {9, 0.03}});
}

}  // namespace
}  // namespace tactus::imaging
