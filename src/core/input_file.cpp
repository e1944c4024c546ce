#include "core/input_file.hpp"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <string_view>

#include "core/error.hpp"

namespace tactus {

std::size_t max_input_bytes() {
  constexpr std::size_t kDefault = std::size_t{1} << 30;
  const char* env = std::getenv("TACTUS_MAX_INPUT_BYTES");
  if (!env || !*env) return kDefault;
  std::size_t value = 0;
  const std::string_view text(env);
  const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
  return r.ec == std::errc() && r.ptr == text.data() + text.size() && value > 0 ? value : kDefault;
}

std::string read_input_file(const std::filesystem::path& path) {
  const SourceLocation where{path.string(), {}, {}, {}};
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(where, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where, "cannot open file for reading");
  const std::size_t limit = max_input_bytes();
  std::string data;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    const auto got = static_cast<std::size_t>(in.gcount());
    if (data.size() + got > limit)
      throw InputError(where, "larger than " + std::to_string(limit) +
                                  " bytes, the limit on an input file (TACTUS_MAX_INPUT_BYTES raises it)");
    data.append(buffer, got);
  }
  if (in.bad()) throw InputError(where, "error while reading file");
  return data;
}

}  // namespace tactus
