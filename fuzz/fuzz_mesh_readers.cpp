// libFuzzer target for the mesh readers. Whole files starting with '<' go to the VTU reader
// and whole files starting with '$' to the MSH reader (ASCII or binary), so that real files
// are seeds as they are. Otherwise the first byte picks the format ('v': legacy VTK;
// otherwise its value modulo 6) and the rest is the file's content, parsed from memory.
// For TetGen the content is split at NUL bytes into .node, .ele and .face. InputError is the expected outcome for bad input; any
// other exception, crash or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "mesh/io/io_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tactus::mesh::io;
  if (size == 0) return 0;
  const std::string_view whole(reinterpret_cast<const char*>(data), size);
  const std::string_view body = whole.substr(1);
  try {
    if (data[0] == '<') {
      (void)parse_vtu(whole, "fuzz.vtu");
      return 0;
    }
    if (data[0] == '$') {
      (void)parse_msh(whole, "fuzz.msh");
      return 0;
    }
    if (data[0] == 'v') {
      (void)parse_vtk(body, "fuzz.vtk");
      return 0;
    }
    switch (data[0] % 6) {
      case 0: (void)parse_obj(body, "fuzz.obj"); break;
      case 1: (void)parse_stl(body, "fuzz.stl"); break;
      case 2: (void)parse_off(body, "fuzz.off"); break;
      case 3: (void)parse_ply(body, "fuzz.ply"); break;
      case 4: (void)parse_msh(body, "fuzz.msh"); break;
      default: {
        const auto a = body.find('\0');
        const std::string_view node = body.substr(0, a);
        std::string_view ele, face;
        bool has_ele = false, has_face = false;
        if (a != std::string_view::npos) {
          const auto rest = body.substr(a + 1);
          const auto b = rest.find('\0');
          ele = rest.substr(0, b);
          has_ele = true;
          if (b != std::string_view::npos) {
            face = rest.substr(b + 1);
            has_face = true;
          }
        }
        (void)parse_tetgen(node, "fuzz.node", has_ele ? &ele : nullptr, "fuzz.ele", has_face ? &face : nullptr,
                           "fuzz.face");
      }
    }
  } catch (const tactus::InputError&) {
  }
  return 0;
}
