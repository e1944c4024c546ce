#pragma once
// The checkpoint of a build in progress: every outcome is appended to a side file as it
// arrives, flushed to the operating system before the next one. A killed build leaves the
// journal behind; `--resume` reads it back (a record cut short by the kill is dropped and
// computed again) and goes on appending. The finished build writes the HDF5 file and
// removes the journal. Layout: docs/precompute.md.
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "precompute/space.hpp"

namespace tactus::precompute {

class Journal {
 public:
  /// Creates a new journal at `path` for `space` (its identity, grid and dof count).
  static Journal create(const std::filesystem::path& path, const Space& space);
  /// Opens an existing journal, stores its complete records into `space` (allocated) and
  /// positions after the last one. Throws InputError when it belongs to another model or
  /// grid.
  static Journal resume(const std::filesystem::path& path, Space& space);

  Journal(Journal&& other) noexcept;
  Journal& operator=(Journal&&) = delete;
  Journal(const Journal&) = delete;
  ~Journal();

  void append(const PointResult& r);
  /// Records read back by resume().
  [[nodiscard]] std::size_t recovered() const { return recovered_; }
  void close();

 private:
  Journal(std::FILE* file, std::filesystem::path path) : file_(file), path_(std::move(path)) {}
  std::FILE* file_ = nullptr;
  std::filesystem::path path_;
  std::size_t recovered_ = 0;
};

}  // namespace tactus::precompute
