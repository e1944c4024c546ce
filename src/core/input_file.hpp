#pragma once
// Reading a user's input file whole (a mesh, a scene), bounded: a directory, a device that
// never ends (/dev/zero) or a file larger than the limit is refused with the reason instead
// of being read until memory runs out.
#include <cstddef>
#include <filesystem>
#include <string>

namespace tactus {

/// The largest input file read whole: 1 GiB, or TACTUS_MAX_INPUT_BYTES (bytes) when set.
[[nodiscard]] std::size_t max_input_bytes();

/// The whole file. Throws InputError naming the path when it is a directory, cannot be
/// opened or read, or holds more than max_input_bytes().
[[nodiscard]] std::string read_input_file(const std::filesystem::path& path);

}  // namespace tactus
