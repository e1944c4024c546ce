#include "mesh/tetrahedralize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <new>
#include <vector>

#include <fmt/format.h>
#include <tetgen.h>

#include "core/child_process.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "mesh/validate.hpp"

namespace tactus::mesh {
namespace {

std::string tetgen_error(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "the surface intersects itself";
    case 4: return "a feature is too small for the mesh (nearly coincident points or edges)";
    case 5: return "two facets are too close to each other";
    case 10: return "invalid input";
    default: return fmt::format("error code {}", code);
  }
}

void require_closed_manifold(const TriMesh& surface) {
  const ValidationReport report = validate(surface, SurfaceChecks{.require_closed = true});
  if (report.ok()) return;
  std::string reasons;
  int shown = 0;
  for (const auto& p : report.problems) {
    if (p.severity != Severity::error) continue;
    if (shown++ == 3) break;
    reasons += "; " + p.what;
  }
  throw InputError(fmt::format("cannot tetrahedralize: the surface is not a closed manifold ({} errors{})",
                               report.count(Severity::error), reasons));
}

}  // namespace

std::string tetgen_switches(const TetrahedralizeOptions& options) {
  std::string s = fmt::format("pzq{}", options.radius_edge_ratio);
  if (options.min_dihedral_deg > 0.0) s += fmt::format("/{}", options.min_dihedral_deg);
  if (options.max_volume) s += fmt::format("a{:.17g}", *options.max_volume);
  if (options.preserve_surface) s += "Y";
  if (options.quiet) s += "Q";
  return s;
}

namespace {

void check_options(const TetrahedralizeOptions& options) {
  if (!(options.radius_edge_ratio >= 1.0) || !std::isfinite(options.radius_edge_ratio))
    throw InputError(fmt::format("tetrahedralize: radius-edge ratio must be >= 1, got {}", options.radius_edge_ratio));
  if (options.max_volume && !(*options.max_volume > 0.0 && std::isfinite(*options.max_volume)))
    throw InputError(fmt::format("tetrahedralize: max volume must be positive, got {}", *options.max_volume));
  if (!(options.min_dihedral_deg >= 0.0 && options.min_dihedral_deg < 70.0))
    throw InputError(fmt::format("tetrahedralize: min dihedral angle must be in [0, 70) degrees, got {}",
                                 options.min_dihedral_deg));
}

// tetgenio frees its arrays with delete[], so they are allocated with new[].
void fill_input(const TriMesh& surface, tetgenio& in) {
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(surface.vertices.size());
  in.pointlist = new REAL[3 * surface.vertices.size()];
  for (std::size_t v = 0; v < surface.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) in.pointlist[3 * v + a] = surface.vertices[v][a];
  in.numberoffacets = static_cast<int>(surface.triangles.size());
  in.facetlist = new tetgenio::facet[surface.triangles.size()];
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = surface.triangles[f][k];
  }
}

// ---- running TetGen within a budget: the child sends back a status byte, then the mesh
// (vertex count, coordinates, tet count, corners) or the reason it failed.

enum class JobStatus : char { ok, input_error, out_of_memory };

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

std::string encode(const TetMesh& mesh) {
  std::string out(1, static_cast<char>(JobStatus::ok));
  put(out, static_cast<std::uint64_t>(mesh.vertices.size()));
  for (const auto& v : mesh.vertices) out.append(reinterpret_cast<const char*>(v.data()), 3 * sizeof(double));
  put(out, static_cast<std::uint64_t>(mesh.tets.size()));
  for (const auto& t : mesh.tets) out.append(reinterpret_cast<const char*>(t.data()), 4 * sizeof(Index));
  return out;
}

class Decoder {
 public:
  explicit Decoder(const std::string& data) : data_(data) {}
  void read(void* to, std::size_t n) {
    if (data_.size() - pos_ < n) throw std::runtime_error("tetrahedralize: truncated result from the TetGen process");
    std::memcpy(to, data_.data() + pos_, n);
    pos_ += n;
  }
  std::uint64_t count(std::size_t each) {
    std::uint64_t n = 0;
    read(&n, sizeof n);
    if (n > (data_.size() - pos_) / each) throw std::runtime_error("tetrahedralize: bad result from the TetGen process");
    return n;
  }
  [[nodiscard]] std::string rest() const { return data_.substr(pos_); }

 private:
  const std::string& data_;
  std::size_t pos_ = 0;
};

TetMesh decode(const std::string& data) {
  Decoder in(data);
  char status = 0;
  in.read(&status, 1);
  if (status == static_cast<char>(JobStatus::input_error)) throw InputError(in.rest());
  if (status == static_cast<char>(JobStatus::out_of_memory))
    throw InputError("TetGen ran out of memory within the allowed " + in.rest() +
                     " (tactus mesh --max-memory raises it)");
  TetMesh mesh;
  mesh.vertices.resize(in.count(3 * sizeof(double)));
  for (auto& v : mesh.vertices) in.read(v.data(), 3 * sizeof(double));
  mesh.tets.resize(in.count(4 * sizeof(Index)));
  for (auto& t : mesh.tets) in.read(t.data(), 4 * sizeof(Index));
  return mesh;
}

/// The budget's deadline, fixed when a call starts, so that a search of several TetGen
/// runs shares one limit.
struct Deadline {
  TetGenBudget budget;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  [[nodiscard]] double seconds_left() const {
    return budget.seconds - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

std::string mib(std::size_t bytes) { return fmt::format("{:.0f} MiB", static_cast<double>(bytes) / (1 << 20)); }

/// Runs `job` (which calls TetGen) in-process when unbounded, else in a child process
/// that is killed at the deadline.
TetMesh run_within(const Deadline& deadline, const std::function<TetMesh()>& job) {
  if (!deadline.budget.bounded()) return job();
  const auto limit_text = [&] { return fmt::format("{:g} s", deadline.budget.seconds); };
  ChildLimits limits;
  limits.memory_bytes = deadline.budget.memory_bytes;
  if (deadline.budget.seconds > 0.0) {
    limits.seconds = deadline.seconds_left();
    if (limits.seconds <= 0.0)
      throw InputError(fmt::format("tetrahedralization did not finish within {} (tactus mesh --timeout raises the "
                                   "limit; a looser --quality or --min-dihedral, or a coarser surface, needs less)",
                                   limit_text()));
  }
  limits.progress_label = "TetGen";
  const std::size_t memory = deadline.budget.memory_bytes;
  const ChildResult r = run_in_child(
      [&job, memory]() -> std::string {
        try {
          return encode(job());
        } catch (const InputError& e) {
          return std::string(1, static_cast<char>(JobStatus::input_error)) + e.reason();
        } catch (const std::bad_alloc&) {
          return std::string(1, static_cast<char>(JobStatus::out_of_memory)) + mib(memory);
        }
      },
      limits);
  switch (r.outcome) {
    case ChildOutcome::finished:
      try {
        return decode(r.output);
      } catch (const InputError& e) {
        // TetGen reports a failed allocation as its own error code.
        if (memory == 0 || e.reason().find("out of memory") == std::string::npos) throw;
        throw InputError(e.reason() + fmt::format(" (its memory capped at {}; tactus mesh --max-memory raises the cap)",
                                                  mib(memory)));
      }
    case ChildOutcome::timed_out:
      throw InputError(fmt::format("tetrahedralization did not finish within {} (tactus mesh --timeout raises the "
                                   "limit; a looser --quality or --min-dihedral, or a coarser surface, needs less)",
                                   limit_text()));
    case ChildOutcome::failed: break;
  }
  if (memory > 0)
    throw InputError(fmt::format("TetGen stopped ({}) with its memory capped at {} (tactus mesh --max-memory "
                                 "raises the cap)",
                                 r.signal ? fmt::format("signal {}", r.signal) : std::string("an error"), mib(memory)));
  throw InputError(fmt::format("TetGen crashed ({})",
                               r.signal ? fmt::format("signal {}", r.signal) : std::string("an internal error")));
}

void run_tetgen(std::string switches, tetgenio& in, tetgenio& out) {
  try {
    ::tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw InputError(fmt::format("TetGen failed ({}): {}", switches, tetgen_error(code)));
  }
}

// TetGen 1.5 crashes while cleaning up after it finds a self-intersection during meshing,
// so intersections are looked for first with its detection-only mode (d).
void tetgen_self_intersections(const TriMesh& surface) {
  tetgenio in, out;
  fill_input(surface, in);
  run_tetgen("pzdQ", in, out);
  if (out.numberoftrifaces > 0) {
    const int* f = out.trifacelist;
    throw InputError(fmt::format("cannot tetrahedralize: the surface intersects itself ({} triangles involved, "
                                 "e.g. the one with vertices {} {} {})",
                                 out.numberoftrifaces, f[0], f[1], f[2]));
  }
}

void check_self_intersections(const TriMesh& surface, const Deadline& deadline) {
  run_within(deadline, [&] {
    tetgen_self_intersections(surface);
    return TetMesh{};
  });
}

TetMesh tetrahedralize_checked(const TriMesh& surface, const TetrahedralizeOptions& options) {
  tetgenio in, out;
  fill_input(surface, in);
  run_tetgen(tetgen_switches(options), in, out);

  TetMesh mesh;
  mesh.vertices.resize(static_cast<std::size_t>(out.numberofpoints));
  for (int v = 0; v < out.numberofpoints; ++v)
    mesh.vertices[v] = Vec3(out.pointlist[3 * v], out.pointlist[3 * v + 1], out.pointlist[3 * v + 2]);
  mesh.tets.resize(static_cast<std::size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    Tet e{};
    for (int k = 0; k < 4; ++k) e[k] = out.tetrahedronlist[t * out.numberofcorners + k];
    // TetGen 1.5 already orders corners so that (v1-v0)·((v2-v0)×(v3-v0)) > 0; the
    // per-tet check keeps that guarantee independent of the library's build or version.
    if (signed_tet_volume(mesh.vertices[e[0]], mesh.vertices[e[1]], mesh.vertices[e[2]], mesh.vertices[e[3]]) < 0.0)
      std::swap(e[0], e[1]);
    mesh.tets[t] = e;
  }
  return mesh;
}

}  // namespace

TetMesh tetrahedralize(const TriMesh& closed_surface, const TetrahedralizeOptions& options) {
  check_options(options);
  require_closed_manifold(closed_surface);
  const Deadline deadline{options.budget};
  check_self_intersections(closed_surface, deadline);
  return run_within(deadline, [&] { return tetrahedralize_checked(closed_surface, options); });
}

NodeCountResult tetrahedralize_to_node_count_detailed(const TriMesh& closed_surface, std::size_t target_nodes,
                                                      double radius_edge_ratio, double tolerance,
                                                      bool preserve_surface, const TetGenBudget& budget) {
  const Deadline deadline{budget};
  if (target_nodes < 4) throw InputError(fmt::format("tetrahedralize: target node count {} is below 4", target_nodes));
  const double volume = closed_surface.signed_volume();
  const auto target = static_cast<double>(target_nodes);
  const auto within = [&](std::size_t nodes) { return std::abs(static_cast<double>(nodes) - target) <= tolerance * target; };
  const auto run = [&](std::optional<double> max_volume) {
    TetrahedralizeOptions options;
    options.max_volume = max_volume;
    options.radius_edge_ratio = radius_edge_ratio;
    options.preserve_surface = preserve_surface;
    return run_within(deadline, [&] { return tetrahedralize_checked(closed_surface, options); });
  };
  TetrahedralizeOptions checked;
  checked.radius_edge_ratio = radius_edge_ratio;
  check_options(checked);
  require_closed_manifold(closed_surface);
  check_self_intersections(closed_surface, deadline);

  // The coarsest mesh the surface and the quality bound allow.
  TetMesh coarse = run(std::nullopt);
  if (within(coarse.vertices.size())) return {std::move(coarse), volume};
  if (coarse.vertices.size() > target)
    throw InputError(fmt::format("tetrahedralize: the surface needs at least {} nodes at quality {} "
                                 "(target {}); use a coarser surface",
                                 coarse.vertices.size(), radius_edge_ratio, target_nodes));

  // Node count falls as max_volume grows: bisect log(max_volume). A tet mesh has about
  // 5-6 tets per node, so the mean tet of the target mesh bounds the bracket.
  double lo = std::log(volume / (target * 50.0));  // too many nodes
  double hi = std::log(volume);                     // too few
  NodeCountResult best{std::move(coarse), volume};
  double best_error = std::abs(static_cast<double>(best.mesh.vertices.size()) - target);
  constexpr int kMaxSteps = 40;
  Progress progress("tetrahedralize", kMaxSteps);
  for (int step = 0; step < kMaxSteps; ++step) {
    progress.update(static_cast<std::size_t>(step));
    const double mid = 0.5 * (lo + hi);
    TetMesh mesh = run(std::exp(mid));
    const std::size_t nodes = mesh.vertices.size();
    const double error = std::abs(static_cast<double>(nodes) - target);
    if (error < best_error) {
      best_error = error;
      best = {std::move(mesh), std::exp(mid)};
    }
    if (within(nodes)) break;
    (static_cast<double>(nodes) > target ? lo : hi) = mid;
  }
  progress.finish();
  if (!within(best.mesh.vertices.size()))
    throw InputError(fmt::format("tetrahedralize: no max volume gives {} nodes within {}% (closest: {})",
                                 target_nodes, 100.0 * tolerance, best.mesh.vertices.size()));
  return best;
}

TetMesh tetrahedralize_to_node_count(const TriMesh& closed_surface, std::size_t target_nodes,
                                     double radius_edge_ratio, double tolerance, bool preserve_surface,
                                     const TetGenBudget& budget) {
  return tetrahedralize_to_node_count_detailed(closed_surface, target_nodes, radius_edge_ratio, tolerance,
                                               preserve_surface, budget)
      .mesh;
}

}  // namespace tactus::mesh
