#include "lod/impostor_cache.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace tactus::lod {
namespace {

ImpostorParams small_params() {
  ImpostorParams p;
  p.coarse_levels = 1;
  p.subdivision_levels = 1;
  p.error_samples = 256;
  p.cost_queries = 32;
  return p;
}

const mesh::TriMesh& input() {
  static const mesh::TriMesh m = mesh::sphere(0.05, 2);
  return m;
}

const ImpostorHierarchy& built() {
  static const ImpostorHierarchy h = build_impostors(input(), small_params());
  return h;
}

std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("tactus_lod_cache_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The error decoding `bytes` gives; fails the test when there is none.
InputError decode_error(std::span<const std::uint8_t> bytes) {
  try {
    (void)decode_impostor_cache(bytes, "cache.tlod", CacheKey{built().mesh_hash, built().params});
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "decoded " << bytes.size() << " bytes without an error";
  return InputError("none");
}

void expect_same(const ImpostorHierarchy& a, const ImpostorHierarchy& b) {
  EXPECT_EQ(a.mesh_hash, b.mesh_hash);
  EXPECT_EQ(a.params, b.params);
  EXPECT_EQ(a.input_level, b.input_level);
  EXPECT_EQ(a.curvature_radius, b.curvature_radius);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t l = 0; l < a.levels.size(); ++l) {
    EXPECT_EQ(a.levels[l].mesh.vertices, b.levels[l].mesh.vertices);
    EXPECT_EQ(a.levels[l].mesh.triangles, b.levels[l].mesh.triangles);
    EXPECT_EQ(a.levels[l].error, b.levels[l].error);
    EXPECT_EQ(a.levels[l].cost, b.levels[l].cost);
    EXPECT_EQ(a.levels[l].rings, b.levels[l].rings);
    EXPECT_EQ(a.levels[l].mean_edge, b.levels[l].mean_edge);
    ASSERT_EQ(a.levels[l].curvature.size(), b.levels[l].curvature.size());
    for (std::size_t v = 0; v < a.levels[l].curvature.size(); ++v)
      EXPECT_EQ(a.levels[l].curvature[v].kmean, b.levels[l].curvature[v].kmean);
    EXPECT_EQ(a.levels[l].bvh.triangle_count(), b.levels[l].bvh.triangle_count());
  }
}

TEST(ImpostorCache, RoundTripsExactly) {
  const std::vector<std::uint8_t> bytes = encode_impostor_cache(built());
  const ImpostorHierarchy decoded =
      decode_impostor_cache(bytes, "cache.tlod", CacheKey{input().content_hash(), small_params()});
  expect_same(built(), decoded);
  EXPECT_EQ(encode_impostor_cache(decoded), bytes);

  const std::filesystem::path dir = scratch("round_trip");
  const std::filesystem::path path = impostor_cache_path(dir, built().mesh_hash);
  EXPECT_EQ(path.extension(), ".tlod");
  EXPECT_EQ(path.stem().string().size(), 16U);
  save_impostor_cache(path, built());
  expect_same(built(), load_impostor_cache(path, input(), small_params()));
  std::filesystem::remove_all(dir);
}

TEST(ImpostorCache, LoadOrBuildBuildsOnceThenLoads) {
  const std::filesystem::path dir = scratch("load_or_build");
  std::string reason;
  const ImpostorHierarchy first = load_or_build_impostors(dir / "objects", input(), small_params(), &reason);
  EXPECT_NE(reason.find("no such file"), std::string::npos) << reason;
  const ImpostorHierarchy second = load_or_build_impostors(dir / "objects", input(), small_params(), &reason);
  EXPECT_EQ(reason, "");
  expect_same(first, second);
  // Other parameters: the file is refused, rebuilt and replaced.
  ImpostorParams other = small_params();
  other.reduction = 0.5;
  const ImpostorHierarchy third = load_or_build_impostors(dir / "objects", input(), other, &reason);
  EXPECT_NE(reason.find("reduction"), std::string::npos) << reason;
  EXPECT_EQ(third.params, other);
  std::filesystem::remove_all(dir);
}

TEST(ImpostorCache, RefusesAnotherMeshOrOtherParametersNamingTheFile) {
  const std::filesystem::path dir = scratch("mismatch");
  const std::filesystem::path path = dir / "object.tlod";
  save_impostor_cache(path, built());
  try {
    (void)load_impostor_cache(path, mesh::sphere(0.05, 1), small_params());
    ADD_FAILURE() << "a cache for another mesh was loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path.string());
    EXPECT_EQ(e.where().byte_offset, 12U);
    EXPECT_NE(e.reason().find("another mesh"), std::string::npos) << e.what();
  }
  ImpostorParams other = small_params();
  other.subdivision_levels = 2;
  try {
    (void)load_impostor_cache(path, input(), other);
    ADD_FAILURE() << "a cache with other parameters was loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path.string());
    EXPECT_EQ(e.where().byte_offset, 20U);
    EXPECT_NE(e.reason().find("subdivision_levels 1 in the file, 2 wanted"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)load_impostor_cache(dir / "missing.tlod", input(), small_params()), InputError);
  std::filesystem::remove_all(dir);
}

TEST(ImpostorCache, RefusesEveryTruncationWithItsOffset) {
  const std::vector<std::uint8_t> bytes = encode_impostor_cache(built());
  for (std::size_t size = 0; size < bytes.size(); size += (size < 256 || size + 256 > bytes.size()) ? 1 : 29) {
    const InputError e = decode_error(std::span(bytes).first(size));
    ASSERT_TRUE(e.where().byte_offset.has_value()) << e.what();
    EXPECT_LE(*e.where().byte_offset, size);
    EXPECT_EQ(e.where().file, "cache.tlod");
  }
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  const InputError e = decode_error(longer);
  EXPECT_EQ(e.where().byte_offset, bytes.size());
  EXPECT_NE(e.reason().find("after the end"), std::string::npos);
}

TEST(ImpostorCache, RefusesGarbageAndEveryFlippedByte) {
  std::mt19937_64 random(17);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<std::uint8_t> garbage(static_cast<std::size_t>(random() % 4096));
    for (std::uint8_t& b : garbage) b = static_cast<std::uint8_t>(random());
    if (trial % 2 == 0 && garbage.size() >= 8) std::copy_n("TLODCACH", 8, garbage.begin());
    const InputError e = decode_error(garbage);
    EXPECT_TRUE(e.where().byte_offset.has_value()) << e.what();
  }
  const std::vector<std::uint8_t> bytes = encode_impostor_cache(built());
  EXPECT_EQ(decode_error(std::vector<std::uint8_t>(bytes.size(), 0)).where().byte_offset, 0U);
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<std::uint8_t> damaged = bytes;
    const std::size_t at = random() % damaged.size();
    damaged[at] ^= static_cast<std::uint8_t>(1U << (random() % 8));
    const InputError e = decode_error(damaged);
    ASSERT_TRUE(e.where().byte_offset.has_value()) << e.what();
  }
  // A huge count is refused before anything is allocated.
  std::vector<std::uint8_t> huge = bytes;
  const std::size_t first_level = 76;  // after the header (docs/lod.md)
  for (int i = 0; i < 4; ++i) huge[first_level + static_cast<std::size_t>(i)] = 0xff;
  const InputError e = decode_error(huge);
  EXPECT_EQ(e.where().byte_offset, first_level + 8);
  EXPECT_NE(e.reason().find("truncated"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace tactus::lod
