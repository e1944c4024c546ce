#pragma once
// Mesh validation: every problem found, each naming the element and what is wrong.
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

enum class Severity { warning, error };

struct Problem {
  Severity severity;
  std::string what;  ///< e.g. "triangle 12: degenerate (area 0)"
};

struct ValidationReport {
  std::vector<Problem> problems;
  [[nodiscard]] bool ok() const;  ///< no errors (warnings allowed)
  [[nodiscard]] std::size_t count(Severity s) const;
};

struct SurfaceChecks {
  bool require_closed = false;  ///< open boundary edges become errors, not warnings
};

ValidationReport validate(const TriMesh& mesh, const SurfaceChecks& checks = {});
ValidationReport validate(const TetMesh& mesh);

}  // namespace tactus::mesh
