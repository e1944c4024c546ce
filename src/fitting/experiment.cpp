#include "fitting/experiment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "core/text.hpp"
#include "scene/toml_reader.hpp"

namespace tactus::fitting {
namespace {

using scene::detail::Context;
using scene::detail::Range;
using scene::detail::Reader;

/// The elastic parameters a law is fitted by, in order.
std::vector<std::string> elastic_keys(const Experiment& e, bool mu_kappa) {
  using physics::FemLaw;
  const FemLaw law = e.law;
  // A spring network has no Poisson ratio of its own (1/4 at best: Cauchy's relation).
  if (e.mass_spring) return {"young_modulus"};
  if (law == FemLaw::mooney_rivlin) return {"c10", "c01", "kappa"};
  if (law == FemLaw::neo_hookean && mu_kappa) return {"mu", "kappa"};
  return {"young_modulus", "poisson_ratio"};
}

Range range_of(const std::string& key) {
  if (key == "poisson_ratio") return Range::open(-1.0, 0.5);
  if (key == "c01") return Range::non_negative();
  return Range::positive();
}

void read_indenter(Reader r, Experiment& e) {
  Indenter& i = e.indenter;
  i.shape = r.choice<IndenterShape>("shape",
                                    {{"sphere", IndenterShape::sphere},
                                     {"flat_punch", IndenterShape::flat_punch},
                                     {"finger", IndenterShape::finger},
                                     {"fingerpad", IndenterShape::fingerpad}},
                                    std::nullopt);
  i.radius = r.required_number("radius", Range::positive());
  const bool finger = i.shape == IndenterShape::finger, pad = i.shape == IndenterShape::fingerpad;
  for (const char* key : {"young_modulus", "poisson_ratio"})
    if (!finger && r.has(key)) r.fail(key, fmt::format("'{}' is a finger's (shape = \"finger\")", key));
  for (const char* key : {"b", "m"})
    if (!pad && r.has(key)) r.fail(key, fmt::format("'{}' is a fingerpad's (shape = \"fingerpad\")", key));
  if (finger) {
    i.finger.youngs_modulus = r.number("young_modulus", i.finger.youngs_modulus, Range::positive());
    i.finger.poisson_ratio = r.number("poisson_ratio", i.finger.poisson_ratio, Range::open_closed(-1.0, 0.5));
  }
  if (pad) {
    i.pad.b = r.number("b", i.pad.b, Range::positive());
    i.pad.m = r.number("m", i.pad.m, Range::positive());
    try {
      (void)contact::FingerpadLaw(i.pad);  // its own checks (e^{m·d} finite)
    } catch (const InputError& err) {
      r.fail("m", err.what());
    }
  }
  r.finish();
}

void read_specimen(Reader r, Experiment& e) {
  Specimen& s = e.specimen;
  if (const auto mesh = r.string("mesh")) {
    s.mesh = *mesh;
    if (s.mesh.is_relative()) s.mesh = r.context().base_dir / s.mesh;
  }
  const auto size = r.vec2("size");
  const auto thickness = r.number("thickness", Range::positive());
  const auto cells = r.integer_list("cells", 1, 200);
  const auto refine = r.number("refine", Range::closed(1.0, 10.0));
  if (s.mesh.empty()) {
    if (!size) r.fail_missing("size", "[x, y] extent of the block [m], or 'mesh'");
    if (!thickness) r.fail_missing("thickness", "the block's thickness [m], or 'mesh'");
    if (size->x() <= 0 || size->y() <= 0) r.fail("size", "both extents must be > 0");
    s.size = *size;
    s.thickness = *thickness;
    s.refine = refine.value_or(1.0);
    if (!cells.empty()) {
      if (cells.size() != 3) r.fail("cells", "expected [cells_x, cells_y, cells_z]");
      for (int k = 0; k < 3; ++k) s.cells[static_cast<std::size_t>(k)] = static_cast<int>(cells[static_cast<std::size_t>(k)]);
    }
  } else if (size || thickness || !cells.empty() || refine) {
    r.fail("mesh", "give either 'mesh' or the generated block's 'size', 'thickness', 'cells' and 'refine', not both");
  }
  s.bottom = r.choice<Support>("bottom", {{"fixed", Support::fixed}, {"sliding", Support::sliding}}, Support::fixed);
  r.finish();
}

void read_material(Reader r, Experiment& e, const std::vector<std::string>& free) {
  // A FemLaw, or none for a spring network.
  const auto model = r.choice<std::optional<physics::FemLaw>>("model",
                                                              {{"linear", physics::FemLaw::linear},
                                                               {"corotational", physics::FemLaw::corotational},
                                                               {"stvk", physics::FemLaw::stvk},
                                                               {"neo_hookean", physics::FemLaw::neo_hookean},
                                                               {"mooney_rivlin", physics::FemLaw::mooney_rivlin},
                                                               {"mass_spring", std::nullopt}},
                                                              physics::FemLaw::corotational);
  e.mass_spring = !model;
  if (model) e.law = *model;
  e.density = r.number("density", 1000.0, Range::positive());
  std::set<std::string> given;
  const std::vector<std::string> all = {"young_modulus", "poisson_ratio", "mu", "kappa", "c10", "c01"};
  std::vector<std::optional<double>> values;
  for (const auto& k : all) {
    values.push_back(r.number(k, range_of(k)));
    if (values.back()) given.insert(k);
  }
  const bool mu_kappa = given.count("mu") || std::count(free.begin(), free.end(), "mu") ||
                        (e.law == physics::FemLaw::neo_hookean && given.count("kappa"));
  const auto keys = elastic_keys(e, mu_kappa);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (given.count(all[i]) && std::find(keys.begin(), keys.end(), all[i]) == keys.end())
      r.fail(all[i], fmt::format("a {} material is fitted by {}; '{}' does not belong with them{}", e.model_name(),
                                 fmt::join(keys, ", "), all[i],
                                 e.mass_spring ? " (a spring network's Poisson ratio is 1/4 at best)" : ""));
  for (const auto& k : keys) {
    Parameter p;
    p.name = k;
    p.value = values[static_cast<std::size_t>(std::find(all.begin(), all.end(), k) - all.begin())];
    if (!p.value && k == "poisson_ratio") p.value = 0.45;  // the scene's default
    if (!p.value && k == "c01") p.value = 0.0;
    e.parameters.push_back(p);
  }
  if (auto v = r.table("viscoelastic")) {
    (void)v->choice<int>("model", {{"prony", 0}}, 0);
    auto terms = v->table_array("terms");
    if (terms.empty()) v->fail_missing("terms", "an array of {g, tau} Prony terms");
    for (std::size_t i = 0; i < terms.size(); ++i) {
      Parameter g, tau;
      g.name = fmt::format("g{}", i + 1);
      tau.name = fmt::format("tau{}", i + 1);
      g.value = terms[i].number("g", Range::open(0.0, 1.0));
      tau.value = terms[i].number("tau", Range::positive());
      terms[i].finish();
      e.parameters.push_back(g);
      e.parameters.push_back(tau);
    }
    e.prony_terms = terms.size();
    v->finish();
  }
  r.finish();
}

void read_fit(Reader& root, Experiment& e, const std::vector<std::string>& free) {
  for (const auto& name : free) {
    auto it = std::find_if(e.parameters.begin(), e.parameters.end(), [&](const Parameter& p) { return p.name == name; });
    if (it == e.parameters.end()) {
      std::vector<std::string> names;
      for (const auto& p : e.parameters) names.push_back(p.name);
      root.fail("fit", fmt::format("free parameter '{}' is not one of this material's: {}", name, fmt::join(names, ", ")));
    }
    it->free = true;
  }
  for (const auto& p : e.parameters)
    if (!p.free && !p.value)
      root.fail("material", fmt::format("'{}' is neither given nor listed in fit.free", p.name));
  if (std::none_of(e.parameters.begin(), e.parameters.end(), [](const Parameter& p) { return p.free; }))
    root.fail("fit", "fit.free names no parameter to fit");
}

CurveKind column_kind(std::string_view a, std::string_view b, const SourceLocation& where) {
  if (a == "depth" && b == "force") return CurveKind::depth_force;
  if (a == "time" && b == "force") return CurveKind::time_force;
  if (a == "time" && b == "depth") return CurveKind::time_depth;
  throw InputError(where, fmt::format("header '{},{}': the columns must be depth,force or time,force or "
                                      "time,depth (SI units: m, N, s)",
                                      a, b));
}

}  // namespace

const Parameter* Experiment::find(const std::string& name) const {
  for (const auto& p : parameters)
    if (p.name == name) return &p;
  return nullptr;
}

CsvCurve parse_curve_csv(const std::string& text, const std::string& source_name) {
  CsvCurve c;
  bool header = false;
  std::size_t line_no = 0, pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text::trim(std::string_view(text).substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    const SourceLocation where{source_name, line_no, {}, {}};
    const std::size_t comma = line.find(',');
    if (comma == std::string_view::npos || line.find(',', comma + 1) != std::string_view::npos)
      throw InputError(where, "expected two comma-separated columns");
    const std::string_view a = text::trim(line.substr(0, comma)), b = text::trim(line.substr(comma + 1));
    if (!header) {
      c.kind = column_kind(a, b, where);
      header = true;
    } else {
      const auto x = text::to_double(a), y = text::to_double(b);
      if (!x || !y) throw InputError(where, fmt::format("'{}' is not a pair of numbers", line));
      if (!std::isfinite(*x) || !std::isfinite(*y)) throw InputError(where, "not a finite number (NaN or infinity)");
      const char* what = c.kind == CurveKind::depth_force ? "depth" : "time";
      if (*x < 0) throw InputError(where, fmt::format("{} {} is negative", what, *x));
      if (!c.x.empty() && *x <= c.x.back())
        throw InputError(where, fmt::format("{} {} does not increase (the row before has {})", what, *x, c.x.back()));
      c.x.push_back(*x);
      c.y.push_back(*y);
    }
    if (end == text.size()) break;
  }
  if (!header) throw InputError(SourceLocation{source_name, {}, {}, {}}, "no header line (depth,force, time,force or time,depth)");
  if (c.x.size() < 3) throw InputError(SourceLocation{source_name, {}, {}, {}}, fmt::format("{} data rows; at least 3 are needed", c.x.size()));
  return c;
}

CsvCurve read_curve_csv(const std::filesystem::path& file) {
  return parse_curve_csv(read_input_file(file), file.string());
}

Experiment parse_experiment(const std::string& toml_text, const std::string& source_name,
                            const std::filesystem::path& base_dir) {
  Context ctx;
  ctx.file = source_name;
  ctx.base_dir = base_dir;
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& err) {
    throw InputError(scene::detail::location(ctx, err.source()), std::string(err.description()));
  }
  Reader r(ctx, root, "");
  Experiment e;
  e.file = source_name;
  std::vector<std::string> free;
  if (auto f = r.table("fit")) {
    free = f->string_list("free", {});
    e.max_iterations = f->integer("max_iterations", 100, 1, 10000);
    f->finish();
  } else {
    r.fail_missing("fit", "a [fit] table with free = [...]");
  }
  if (auto t = r.table("indenter")) read_indenter(*t, e);
  else r.fail_missing("indenter", "a table with shape and radius");
  if (auto t = r.table("specimen")) read_specimen(*t, e);
  else r.fail_missing("specimen", "a table with size, thickness, cells (or mesh) and bottom");
  if (auto t = r.table("material")) read_material(*t, e, free);
  else r.fail_missing("material", "a table with model and the law's parameters");
  read_fit(r, e, free);

  auto data = r.table("data");
  if (!data) r.fail_missing("data", "a table with file = \"curve.csv\"");
  e.data_file = data->required_string("file");
  if (e.data_file.is_relative()) e.data_file = base_dir / e.data_file;
  const auto hold_depth = data->number("depth", Range::positive());
  const auto hold_force = data->number("force", Range::positive());
  const auto ramp = data->number("ramp_time", Range::non_negative());
  CsvCurve curve = read_curve_csv(e.data_file);
  e.kind = curve.kind;
  e.x = std::move(curve.x);
  e.y = std::move(curve.y);
  if (e.kind == CurveKind::time_force) {
    if (!hold_depth) data->fail_missing("depth", "the held depth [m] of a relaxation (time,force) curve");
    if (!ramp) data->fail_missing("ramp_time", "the time [s] over which the depth was ramped");
    e.hold = {*hold_depth, *ramp};
  } else if (e.kind == CurveKind::time_depth) {
    if (!hold_force) data->fail_missing("force", "the held force [N] of a creep (time,depth) curve");
    if (!ramp) data->fail_missing("ramp_time", "the time [s] over which the force was ramped");
    if (hold_depth) data->fail("depth", "a creep curve (time,depth) holds a force: give [data] force, not depth");
    e.hold = {*hold_force, *ramp};
  } else if (hold_depth || hold_force || ramp) {
    data->fail("file", "a depth,force curve takes no depth, force or ramp_time");
  }
  if (e.kind == CurveKind::time_force && hold_force)
    data->fail("force", "a relaxation curve (time,force) holds a depth: give [data] depth, not force");
  if (e.kind == CurveKind::depth_force && e.prony_terms > 0)
    r.fail("material", "Prony terms are fitted to a relaxation (time,force) or creep (time,depth) curve; this curve is "
                       "depth,force");
  if (e.kind != CurveKind::depth_force && (e.indenter.shape == IndenterShape::finger ||
                                           e.indenter.shape == IndenterShape::fingerpad))
    r.fail("indenter", "a finger presses loading curves (depth,force); relaxation and creep under a finger are not "
                       "modelled");
  if (e.kind != CurveKind::depth_force && e.prony_terms == 0)
    r.fail("material", "a relaxation (time,force) or creep (time,depth) curve needs [material.viscoelastic] terms to fit");
  data->finish();
  r.finish();
  return e;
}

Experiment read_experiment(const std::filesystem::path& toml_file) {
  return parse_experiment(read_input_file(toml_file), toml_file.string(), toml_file.parent_path());
}

std::string Experiment::model_name() const { return mass_spring ? "mass_spring" : std::string(physics::to_string(law)); }

physics::FemMaterial make_material(const Experiment& e, const std::vector<double>& values) {
  physics::FemMaterial m;
  m.law = e.law;
  m.density = e.density;
  auto value = [&](const char* name) {
    for (std::size_t i = 0; i < e.parameters.size(); ++i)
      if (e.parameters[i].name == name) return values[i];
    return std::numeric_limits<double>::quiet_NaN();
  };
  if (e.mass_spring) {
    m.young_modulus = value("young_modulus");
    m.poisson_ratio = 0.25;  // the network's, at best (Cauchy's relation): what a finger's share takes
  } else if (e.find("young_modulus")) {
    m.young_modulus = value("young_modulus");
    m.poisson_ratio = value("poisson_ratio");
  } else {
    // μ and κ (neo-Hookean), or C10, C01 and κ (Mooney–Rivlin) → E, ν.
    const bool mr = e.find("c10") != nullptr;
    const double mu = mr ? 2.0 * (value("c10") + value("c01")) : value("mu");
    const double kappa = value("kappa");
    m.young_modulus = 9.0 * kappa * mu / (3.0 * kappa + mu);
    m.poisson_ratio = (3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu));
    m.bulk_modulus = kappa;
    if (mr) {
      m.c10 = value("c10");
      m.c01 = value("c01");
    }
  }
  for (std::size_t t = 0; t < e.prony_terms; ++t) {
    const std::string n = std::to_string(t + 1);
    m.prony.push_back({value(("g" + n).c_str()), value(("tau" + n).c_str())});
  }
  m.prony_relaxes_bulk = true;
  return m;
}

}  // namespace tactus::fitting
