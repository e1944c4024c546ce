#pragma once
// Mesh validation: every problem found, each naming the element and what is wrong.
#include <string>
#include <vector>

#include "mesh/file_numbering.hpp"
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

/// Intersecting triangle pairs listed before the rest are only counted.
inline constexpr std::size_t kSelfIntersectionsShown = 5;
/// Vertices closer than this fraction of the bounding-box diagonal are reported as
/// duplicates (a warning: a seam that should have been welded).
inline constexpr double kCoincidentVertices = 1e-9;

/// Every problem found. With `numbering` (what the reader recorded) messages name
/// vertices and elements as the file numbers them, with the line each was read on.
ValidationReport validate(const TriMesh& mesh, const SurfaceChecks& checks = {},
                          const FileNumbering* numbering = nullptr);
ValidationReport validate(const TetMesh& mesh, const FileNumbering* numbering = nullptr);

}  // namespace tactus::mesh
