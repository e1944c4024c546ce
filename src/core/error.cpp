#include "core/error.hpp"

namespace tactus {

std::string SourceLocation::str() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line) {
    s += ":" + std::to_string(*line);
    if (column) s += ":" + std::to_string(*column);
  } else if (byte_offset) {
    s += ": byte " + std::to_string(*byte_offset);
  }
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what)
    : std::runtime_error(where.str() + ": " + what), where_(std::move(where)), reason_(what) {}

InputError::InputError(const std::string& what) : std::runtime_error(what), reason_(what) {}

}  // namespace tactus
