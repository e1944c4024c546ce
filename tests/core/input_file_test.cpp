// Input files read whole, bounded: a directory, a missing file, an endless device and a file
// over the limit are refused with the path and the reason.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/input_file.hpp"

namespace tactus {
namespace {

std::string reason_of(const std::filesystem::path& p) {
  try {
    (void)read_input_file(p);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, p.string());
    return e.reason();
  }
  return "(read)";
}

TEST(InputFile, ReadsAFileWhole) {
  const auto p = std::filesystem::temp_directory_path() / "tactus_input_file_test.txt";
  const std::string text(200000, 'x');
  std::ofstream(p, std::ios::binary) << text;
  EXPECT_EQ(read_input_file(p), text);
  std::filesystem::remove(p);
}

TEST(InputFile, DirectoriesAndMissingFilesAreRefused) {
  EXPECT_EQ(reason_of(std::filesystem::temp_directory_path()), "is a directory, not a file");
  EXPECT_EQ(reason_of("/nonexistent/tactus.obj"), "cannot open file for reading");
}

TEST(InputFile, AnEndlessDeviceStopsAtTheLimit) {
  ::setenv("TACTUS_MAX_INPUT_BYTES", "100000", 1);
  EXPECT_EQ(max_input_bytes(), 100000u);
  EXPECT_EQ(reason_of("/dev/zero"),
            "larger than 100000 bytes, the limit on an input file (TACTUS_MAX_INPUT_BYTES raises it)");
  ::setenv("TACTUS_MAX_INPUT_BYTES", "nonsense", 1);
  EXPECT_EQ(max_input_bytes(), std::size_t{1} << 30);  // the default
  ::unsetenv("TACTUS_MAX_INPUT_BYTES");
  EXPECT_EQ(max_input_bytes(), std::size_t{1} << 30);
}

}  // namespace
}  // namespace tactus
