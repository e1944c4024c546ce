// libFuzzer target for the impostor cache reader (lod/impostor_cache.hpp): any bytes as a
// .tlod file. InputError is the expected outcome for bad input; any other exception, crash or
// sanitizer report is a bug. The seed is a two-level icosphere hierarchy written by
// `tactus run` with a [lod] cache.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.hpp"
#include "lod/impostor_cache.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)tactus::lod::decode_impostor_cache(std::span<const std::uint8_t>(data, size), "fuzz.tlod");
  } catch (const tactus::InputError&) {
  }
  return 0;
}
