#pragma once
// Reads a recording file (docs/recording-format.md), including one cut short by a crash.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "runtime/recording.hpp"

namespace tactus::runtime {

/// Reads the whole file at once. InputError ("file: byte N: reason") if it cannot be read,
/// is not a recording, has a format version this build does not know, or its header chunk
/// is damaged. Damage after the header is not an error: reading stops at the first chunk
/// that is cut short, fails its checksum or does not decode, keeps every record before it,
/// and says why and where in Recording::truncation.
Recording read_recording(const std::filesystem::path& path);

/// The same from bytes in memory; `name` is used in messages.
Recording read_recording(std::span<const std::byte> bytes, std::string name);

}  // namespace tactus::runtime
