#include "core/error.hpp"

namespace tactus {

std::string SourceLocation::str() const {
  // Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on `s += ":" + x`.
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line) {
    s.append(":").append(std::to_string(*line));
    if (column) s.append(":").append(std::to_string(*column));
  } else if (byte_offset) {
    s.append(": byte ").append(std::to_string(*byte_offset));
  }
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what)
    : std::runtime_error(where.str() + ": " + what), where_(std::move(where)), reason_(what) {}

InputError::InputError(const std::string& what) : std::runtime_error(what), reason_(what) {}

}  // namespace tactus
