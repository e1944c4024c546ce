#include "offline/solve.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <memory>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "physics/mapping.hpp"
#include "compile/bodies.hpp"

namespace tactus::offline {
namespace {

/// Reads probe displacements: barycentric in the tet mesh, or the nearest surface node.
class ProbeReader {
 public:
  ProbeReader(const scene::Body& body, const std::vector<scene::Probe>& probes) {
    std::vector<Vec3> points;
    for (const auto& p : probes) points.push_back(p.position);
    if (points.empty()) return;
    if (body.volume) {
      mapping_ = std::make_unique<physics::BarycentricMapping>(*body.volume, points);
    } else {
      for (const Vec3& p : points) {
        std::size_t best = 0;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < body.surface.vertices.size(); ++i)
          if ((body.surface.vertices[i] - p).squaredNorm() < d) {
            d = (body.surface.vertices[i] - p).squaredNorm();
            best = i;
          }
        nearest_.push_back(static_cast<Eigen::Index>(best));
      }
    }
    rest_ = points;
  }

  void read(const VecX& x, const VecX& x0, std::vector<Vec3>& out) const {
    out.clear();
    if (mapping_) {
      std::vector<Vec3> now, then;
      mapping_->apply(x, now);
      mapping_->apply(x0, then);
      for (std::size_t i = 0; i < now.size(); ++i) out.push_back(now[i] - then[i]);
    } else {
      for (auto n : nearest_) out.push_back(x.segment<3>(3 * n) - x0.segment<3>(3 * n));
    }
  }

 private:
  std::unique_ptr<physics::BarycentricMapping> mapping_;
  std::vector<Eigen::Index> nearest_;
  std::vector<Vec3> rest_;
};

/// Reaction on each fixed region and prescribed motion: what the supports must push so that
/// the held nodes stay where they are, −(internal + external + weight) summed over the region.
void reactions(const scene::Body& b, const physics::Body& pb, physics::BodyState& s, const VecX& f_ext,
               VecX& scratch, std::vector<Vec3>& out) {
  scratch.resize(s.x.size());
  pb.model->forces(s.x, s.v, s.q, scratch, *s.model_scratch);
  scratch += f_ext;
  const VecX& m = pb.model->lumped_mass();
  for (Eigen::Index i = 0; i < scratch.size(); ++i) scratch[i] += m[i] * pb.gravity[i % 3];
  out.clear();
  auto sum = [&](const std::vector<mesh::Index>& nodes) {
    Vec3 r = Vec3::Zero();
    for (auto n : nodes) r -= scratch.segment<3>(3 * n);
    out.push_back(r);
  };
  for (const auto& f : b.fixed) sum(f.nodes);
  for (const auto& p : b.prescribed) sum(p.nodes);
}

BodySolve solve_body(const scene::Model& model, std::size_t index, const SolveOptions& o) {
  const scene::Body& b = model.bodies[index];
  const physics::Body pb = compile::make_physics_body(model, index);
  physics::BodyState s = physics::make_state(pb);
  const VecX rest = s.x;

  BodySolve out;
  out.body = b.name;
  std::vector<scene::Probe> probes = b.probes;
  probes.insert(probes.end(), o.extra_probes.begin(), o.extra_probes.end());
  for (const auto& p : probes) out.probe_names.push_back(p.name);
  for (const auto& f : b.fixed) out.region_names.push_back(f.name);
  for (const auto& p : b.prescribed) out.region_names.push_back(p.name);
  const ProbeReader probe_reader(b, probes);

  VecX f_ext = VecX::Zero(s.x.size());
  VecX scratch;
  auto record = [&](double time, int step, int iterations, bool converged) {
    SolveRow row;
    row.time = time;
    row.step = step;
    row.linear_iterations = iterations;
    row.converged = converged;
    probe_reader.read(s.x, rest, row.probe_displacements);
    reactions(b, pb, s, f_ext, scratch, row.reactions);
    out.rows.push_back(std::move(row));
  };

  if (o.static_solve) {
    const scene::StaticSolve& settings = model.static_solve;
    const int steps = b.load_steps;
    Progress progress(o.progress.empty() ? "solving " + b.name : o.progress, static_cast<std::size_t>(steps));
    // Each load step walks from the last equilibrium in sub-steps: the free nodes are first
    // carried along with the held ones (physics::predict_static), then Newton balances. A
    // sub-step that fails is retried at half the size from the last equilibrium, and the
    // load step keeps the smaller size; a load step that still fails at the smallest size
    // ends the body's solve (a later step would start from an unbalanced state).
    VecX equilibrium = s.x;
    double reached = 0.0;
    for (int k = 1; k <= steps && out.failure.empty(); ++k) {
      const double end = k == steps ? 1.0 : static_cast<double>(k) / steps;
      double size = 1.0 / steps;
      int halvings = 0, iterations = 0;
      physics::StaticResult r;
      while (reached < end) {
        const double s_k = std::min(end, reached + size);
        auto fraction = [s_k](double) { return s_k; };
        compile::assemble_loads(b, fraction, f_ext);
        compile::place_prescribed(b, rest, fraction, s.x);
        std::string thrown;  // a linear solve that failed outright (not positive definite)
        try {
          physics::predict_static(pb, s, equilibrium, f_ext);
          r = physics::solve_static(pb, s, f_ext, settings.newton);
        } catch (const std::runtime_error& e) {
          r = {};
          thrown = e.what();
        }
        iterations += r.iterations;
        if (thrown.empty() && r.converged && s.x.allFinite()) {
          reached = s_k;
          equilibrium = s.x;
        } else if (halvings < settings.max_step_halvings) {
          ++halvings;
          size *= 0.5;
          s.x = equilibrium;
        } else {
          std::string reason = thrown;
          if (reason.empty() && r.inverted)
            reason = fmt::format("the balanced state has an element inside out (min volume ratio {:.3g}); the law "
                                 "cannot follow this deformation (a finer mesh or neo_hookean may)",
                                 pb.model->min_volume_ratio(s.x));
          else if (reason.empty())
            reason = fmt::format("Newton stopped at an out-of-balance force of {:.3g} N ({:.3g} of the loads and "
                                 "reactions) after {} iterations{}",
                                 r.residual_force, r.residual, r.iterations,
                                 r.stagnated ? " (line search stagnated)" : "");
          out.failure = fmt::format("load step {}/{} (load fraction {:.6g}){}: {}", k, steps, s_k,
                                    halvings > 0 ? fmt::format(", after {} halvings of the step", halvings) : "",
                                    reason);
          s.x = equilibrium;  // the row and the output mesh show the last equilibrium
          const double last = reached;
          compile::assemble_loads(b, [last](double) { return last; }, f_ext);
          break;
        }
      }
      out.step_halvings += halvings;
      record(reached, k, iterations, out.failure.empty());
      progress.update(static_cast<std::size_t>(k));
    }
  } else {
    const double dt = b.time_step;
    const auto steps = static_cast<long>(std::ceil(o.until / dt - 1e-9));
    if (steps > 100'000'000) throw InputError(fmt::format("--until {} s at dt {} s is over 10^8 steps", o.until, dt));
    Progress progress(o.progress.empty() ? "simulating " + b.name : o.progress, static_cast<std::size_t>(steps));
    double next_report = 0.0;
    record(0.0, 0, 0, true);
    for (long k = 1; k <= steps; ++k) {
      const double t = static_cast<double>(k) * dt;
      auto fraction = [t](double ramp_time) { return compile::ramp(t, ramp_time); };
      compile::assemble_loads(b, fraction, f_ext);
      compile::place_prescribed(b, rest, fraction, s.x);
      physics::step(pb, s, dt, f_ext);
      if (!s.x.allFinite())
        throw std::runtime_error(fmt::format("body '{}' diverged at t = {} s (NaN or infinite positions); "
                                             "reduce time_step or use implicit_euler", b.name, t));
      if (t + 1e-12 >= next_report || k == steps) {
        record(t, static_cast<int>(k), s.last_linear_iterations, true);
        next_report = t + o.report_every;
      }
      progress.update(static_cast<std::size_t>(k));
    }
  }
  out.final_positions.resize(static_cast<std::size_t>(s.x.size() / 3));
  for (std::size_t i = 0; i < out.final_positions.size(); ++i)
    out.final_positions[i] = s.x.segment<3>(3 * static_cast<Eigen::Index>(i));
  return out;
}

}  // namespace

SolveResult solve(const scene::Model& model, const SolveOptions& options) {
  SolveResult result;
  for (std::size_t i = 0; i < model.bodies.size(); ++i)
    if (model.bodies[i].kind != scene::BodyKind::rigid && model.bodies[i].kind != scene::BodyKind::embedded)
      result.bodies.push_back(solve_body(model, i, options));
  if (result.bodies.empty()) throw InputError(SourceLocation{model.source, {}, {}, {}}, "the scene has no deformable body to solve");
  return result;
}

std::string to_csv(const BodySolve& body, bool static_solve) {
  std::string csv = static_solve ? "load_step,load_fraction" : "step,time";
  for (const auto& p : body.probe_names) csv += fmt::format(",{0}_ux,{0}_uy,{0}_uz", p);
  for (const auto& r : body.region_names) csv += fmt::format(",{0}_fx,{0}_fy,{0}_fz", r);
  csv += static_solve ? ",newton_iterations,converged\n" : ",linear_iterations\n";
  for (const auto& row : body.rows) {
    csv += fmt::format("{},{:.9g}", row.step, row.time);
    for (const auto& u : row.probe_displacements) csv += fmt::format(",{:.9g},{:.9g},{:.9g}", u.x(), u.y(), u.z());
    for (const auto& f : row.reactions) csv += fmt::format(",{:.9g},{:.9g},{:.9g}", f.x(), f.y(), f.z());
    csv += static_solve ? fmt::format(",{},{}\n", row.linear_iterations, row.converged ? 1 : 0)
                        : fmt::format(",{}\n", row.linear_iterations);
  }
  return csv;
}

std::vector<scene::Probe> read_probe_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(SourceLocation{path, {}, {}, {}}, "cannot open the probe file");
  std::vector<scene::Probe> probes;
  std::string line;
  std::uint64_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto t = text::trim(line);
    if (t.empty() || t.front() == '#') continue;
    std::vector<std::string> cells;
    std::string cell;
    for (char c : std::string(t)) {
      if (c == ',') {
        cells.push_back(std::string(text::trim(cell)));
        cell.clear();
      } else {
        cell += c;
      }
    }
    cells.push_back(std::string(text::trim(cell)));
    const SourceLocation where{path, number, {}, {}};
    if (cells.size() != 4) throw InputError(where, fmt::format("expected 4 columns 'name,x,y,z', got {}", cells.size()));
    const auto x = text::to_double(cells[1]), y = text::to_double(cells[2]), z = text::to_double(cells[3]);
    if (!x || !y || !z) {
      if (probes.empty() && number == 1) continue;  // a header line
      throw InputError(where, "expected numbers for x, y, z");
    }
    if (cells[0].empty()) throw InputError(where, "empty probe name");
    for (const auto& p : probes)
      if (p.name == cells[0]) throw InputError(where, "duplicate probe name '" + cells[0] + "'");
    if (!std::isfinite(*x) || !std::isfinite(*y) || !std::isfinite(*z)) throw InputError(where, "coordinates must be finite");
    probes.push_back({cells[0], Vec3(*x, *y, *z)});
  }
  if (probes.empty()) throw InputError(SourceLocation{path, {}, {}, {}}, "no probes in the file");
  return probes;
}

}  // namespace tactus::offline
