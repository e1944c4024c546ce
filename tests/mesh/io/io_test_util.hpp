#pragma once
// Shared helpers for the mesh I/O tests: a scratch directory per test and checks on
// the InputError a reader throws.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"

namespace tactus::mesh::test {

/// The bundled meshes, among them files other tools wrote.
inline const std::filesystem::path data_dir = std::filesystem::path(TACTUS_TEST_DATA_DIR) / "meshes";

inline std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::temp_directory_path() /
             ("tactus_io_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
  std::filesystem::remove_all(dir);  // a clean slate on reruns
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path write_bytes(const std::filesystem::path& path, const std::string& data) {
  std::ofstream out(path, std::ios::binary);
  out << data;
  return path;
}

inline std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Where an error is expected: a line (text) or a byte offset (binary), or neither.
struct At {
  At(std::optional<std::uint64_t> l = {}, std::optional<std::uint64_t> b = {}, std::optional<std::uint64_t> c = {})
      : line(l), byte(b), column(c) {}
  std::optional<std::uint64_t> line;
  std::optional<std::uint64_t> byte;
  std::optional<std::uint64_t> column;
};

/// Reads `path` and checks the InputError: its file, its position and that its reason
/// contains `reason`.
inline void expect_read_error(const std::filesystem::path& path, const std::string& reason, At at = {},
                              std::optional<std::filesystem::path> file = {}) {
  try {
    (void)read_mesh(path);
    ADD_FAILURE() << "no error reading " << path << " (wanted '" << reason << "')";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, (file ? *file : path).string()) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << "reason: " << e.reason() << "\nwanted: " << reason;
    if (at.line) {
      EXPECT_EQ(e.where().line, at.line) << e.what();
    }
    if (at.byte) {
      EXPECT_EQ(e.where().byte_offset, at.byte) << e.what();
    }
    if (at.column) {
      EXPECT_EQ(e.where().column, at.column) << e.what();
    }
    // The message names the file so a user can find it.
    EXPECT_NE(std::string(e.what()).find((file ? *file : path).string()), std::string::npos);
  }
}

}  // namespace tactus::mesh::test
