#pragma once
// Errors. InputError is the user's to fix (a bad file, key or flag: exit code 1);
// anything else escaping to the command line is an internal error (exit code 2).
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace tactus {

/// Where in a user's file something is wrong. Line and column are 1-based;
/// byte offsets are used for binary files.
struct SourceLocation {
  std::string file;
  std::optional<std::uint64_t> line;
  std::optional<std::uint64_t> column;
  std::optional<std::uint64_t> byte_offset;

  /// "file:line:column", "file:line", "file@byte N" or "file".
  [[nodiscard]] std::string str() const;
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, const std::string& what);
  explicit InputError(const std::string& what);

  [[nodiscard]] const SourceLocation& where() const { return where_; }
  /// The reason alone, without the location prefix.
  [[nodiscard]] const std::string& reason() const { return reason_; }

 private:
  SourceLocation where_;
  std::string reason_;
};

}  // namespace tactus
