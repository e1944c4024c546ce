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
  /// How many problems this entry stands for: 1, or N for a "... and N more" line that
  /// replaces the messages beyond the per-kind cap.
  std::size_t count = 1;
};

struct ValidationReport {
  std::vector<Problem> problems;
  [[nodiscard]] bool ok() const;  ///< no errors (warnings allowed)
  [[nodiscard]] std::size_t count(Severity s) const;  ///< exact, capped messages included
};

/// Messages printed per kind of problem before the rest are summarised in one line.
inline constexpr std::size_t kMaxMessagesPerKind = 20;

struct SurfaceChecks {
  bool require_closed = false;  ///< open boundary edges become errors, not warnings
};

ValidationReport validate(const TriMesh& mesh, const SurfaceChecks& checks = {});
ValidationReport validate(const TetMesh& mesh);

}  // namespace tactus::mesh
