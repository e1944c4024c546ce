// libFuzzer target for the scene parser: any bytes either load or raise InputError.
// Files are never read (mesh and replay keys fail), and generators get a small budget so
// one input cannot run for minutes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tactus::scene::LoadOptions options;
  options.allow_file_access = false;
  options.max_generated_cells = 20000;
  try {
    const tactus::scene::Model model = tactus::scene::parse_scene(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml", options);
    (void)tactus::scene::summarize(model);
  } catch (const tactus::InputError&) {
    // A clear error is the expected outcome for malformed input.
  }
  return 0;
}
