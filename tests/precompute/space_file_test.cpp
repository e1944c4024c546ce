#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/error.hpp"
#include "precompute/builder.hpp"
#include "precompute/journal.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/space_file.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("tactus_precompute_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

Space built_space(const physics::Body& body, const SpaceSettings& s) {
  Space space = make_space(body, s, "[precompute]\nspacing = 0.003\n");
  BuildOptions o;
  build_local(space, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, o);
  return space;
}

TEST(SpaceFile, RoundTripsEverything) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space space = built_space(body, s);
  const fs::path path = temp_file("roundtrip.h5");
  write_space(path, space);
  const Space back = load_space(path, identify(body, s, space.grid));
  EXPECT_EQ(back.grid.counts, space.grid.counts);
  EXPECT_EQ(back.grid.origin, space.grid.origin);
  EXPECT_EQ(back.grid.spacing, space.grid.spacing);
  EXPECT_EQ(back.start, space.start);
  EXPECT_EQ(back.status, space.status);
  EXPECT_EQ(back.source, space.source);
  EXPECT_EQ(back.force, space.force);
  EXPECT_EQ(back.reason, space.reason);
  EXPECT_TRUE(back.displacement == space.displacement);
  EXPECT_TRUE(back.has_gradients);
  EXPECT_EQ(back.force_gradient, space.force_gradient);
  EXPECT_TRUE(back.displacement_gradient == space.displacement_gradient);
  EXPECT_GT(space.displacement_gradient.norm(), 0.0);
  EXPECT_TRUE(back.has_torques);
  EXPECT_EQ(back.torque, space.torque);
  EXPECT_EQ(back.torque_gradient, space.torque_gradient);
  EXPECT_EQ(back.scene_text, space.scene_text);
  EXPECT_TRUE(back.rest_positions == space.rest_positions);
  EXPECT_EQ(back.elements, space.elements);
  EXPECT_EQ(back.settings.patch_nodes, s.patch_nodes);
  EXPECT_EQ(back.settings.contact_node, s.contact_node);
  fs::remove_all(path.parent_path());
}

TEST(SpaceFile, RefusesAnotherMesh) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space space = built_space(body, s);
  const fs::path path = temp_file("refuse.h5");
  write_space(path, space);
  // Another mesh: a finer box.
  physics::Body other = testing::block_body();
  other.model = std::make_shared<physics::TetFem>(mesh::box_volume(Vec3(0.04, 0.04, 0.02), 4, 4, 3),
                                                  physics::FemMaterial{});
  try {
    (void)load_space(path, identify(other, s, space.grid));
    FAIL() << "loaded a space for another mesh";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  // Same mesh, another material.
  const physics::Body stiffer = testing::block_body(9.0e3);
  EXPECT_THROW((void)load_space(path, identify(stiffer, s, space.grid)), InputError);
  fs::remove_all(path.parent_path());
}

TEST(SpaceFile, RegionsOfTheBodyArePartOfItsIdentity) {
  // The block with its upper layer a second, stiffer region: a space built for it must not be
  // taken for the one-region block, nor for the same regions with another stiffness or
  // another split; the one-region block keeps the identity it always had.
  const physics::Body plain = testing::block_body();
  const SpaceSettings s = testing::block_settings(plain);
  const Grid grid = Grid::through(plain.model->rest_positions().segment<3>(3 * s.contact_node), s.bounds_min,
                                  s.bounds_max, s.spacing);
  const auto layered = [&](double upper_young, double split_z) {
    const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.04, 0.04, 0.02), 4, 4, 2);
    const auto* fem = dynamic_cast<const physics::TetFem*>(plain.model.get());
    std::vector<physics::FemMaterial> materials{fem->material(), fem->material()};
    materials[1].young_modulus = upper_young;
    std::vector<std::int32_t> region;
    for (const auto& t : mesh.tets) {
      double z = 0.0;
      for (const auto v : t) z += 0.25 * mesh.vertices[static_cast<std::size_t>(v)].z();
      region.push_back(z > split_z ? 1 : 0);
    }
    physics::Body body = plain;
    body.model = std::make_shared<physics::TetFem>(mesh, materials, region);
    return identify(body, s, grid);
  };
  const ModelIdentity one = identify(plain, s, grid);
  const ModelIdentity two = layered(2e4, 0.0);
  EXPECT_EQ(two.mesh_hash, one.mesh_hash);
  EXPECT_NE(two.model_hash, one.model_hash);
  EXPECT_NE(layered(3e4, 0.0).model_hash, two.model_hash);
  EXPECT_NE(layered(2e4, -0.009).model_hash, two.model_hash);
  EXPECT_EQ(layered(2e4, 0.0).model_hash, two.model_hash);
  EXPECT_THROW(check_identity(two, one, "block.h5"), InputError);
}

TEST(SpaceFile, MalformedFilesAreInputErrors) {
  const fs::path path = temp_file("bad.h5");
  std::ofstream(path) << "not hdf5";
  EXPECT_THROW((void)read_space(path), InputError);
  EXPECT_THROW((void)read_space(temp_file("missing.h5")), InputError);
  fs::remove_all(path.parent_path());
}

TEST(Journal, RecoversCompleteRecordsAndDropsACutOne) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space full = built_space(body, s);
  const fs::path path = temp_file("space.h5.journal");
  Space partial = full;
  partial.allocate(body.model->node_count());
  {
    Journal j = Journal::create(path, partial);
    for (std::size_t p = 0; p < 5; ++p) {
      PointResult r;
      r.point = p;
      r.status = full.status[p];
      r.source = full.source[p];
      r.force = full.force[p];
      r.reason = full.reason[p];
      r.displacement = full.displacement.col(static_cast<Eigen::Index>(p));
      r.force_gradient = full.force_gradient[p];
      // Made up: the block's one-node patch has no torque, and the journal must keep any.
      r.torque = Vec3(1.0, -2.0, 3.0) * static_cast<double>(p + 1);
      r.torque_gradient = Mat3::Constant(0.5 * static_cast<double>(p));
      r.displacement_gradient = full.displacement_gradient.middleCols<3>(3 * static_cast<Eigen::Index>(p));
      j.append(r);
    }
  }
  // A kill in the middle of the sixth record.
  const auto size = fs::file_size(path);
  { std::ofstream(path, std::ios::app | std::ios::binary) << "TPCR and then nothing"; }
  Space resumed = partial;
  {
    Journal j = Journal::resume(path, resumed);
    EXPECT_EQ(j.recovered(), 5u);
  }
  EXPECT_EQ(fs::file_size(path), size);
  for (std::size_t p = 0; p < 5; ++p) {
    EXPECT_EQ(resumed.status[p], full.status[p]);
    EXPECT_EQ(resumed.force[p], full.force[p]);
    EXPECT_TRUE(resumed.displacement.col(static_cast<Eigen::Index>(p)) ==
                full.displacement.col(static_cast<Eigen::Index>(p)));
    EXPECT_EQ(resumed.force_gradient[p], full.force_gradient[p]);
    if (resumed.status[p] == PointStatus::solved) {
      EXPECT_EQ(resumed.torque[p], (Vec3(1.0, -2.0, 3.0) * static_cast<double>(p + 1)).eval());
      EXPECT_EQ(resumed.torque_gradient[p], Mat3::Constant(0.5 * static_cast<double>(p)).eval());
    }
    EXPECT_TRUE(resumed.displacement_gradient.middleCols<3>(3 * static_cast<Eigen::Index>(p)) ==
                full.displacement_gradient.middleCols<3>(3 * static_cast<Eigen::Index>(p)));
  }
  EXPECT_EQ(resumed.status[5], PointStatus::pending);
  // Another model's journal is refused.
  Space other = partial;
  other.identity.model_hash ^= 1;
  EXPECT_THROW(Journal::resume(path, other), InputError);
  // Journals of the versions before the derivatives and before the torques are refused by
  // name, not misread.
  for (const char version : {'1', '2'}) {
    {
      std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
      f.seekp(7);
      f.put(version);
    }
    Space older = partial;
    try {
      Journal::resume(path, older);
      ADD_FAILURE() << "a version " << version << " journal was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("older version"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(path.parent_path());
}

}  // namespace
}  // namespace tactus::precompute
