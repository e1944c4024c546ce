// Scene text → Model: parses the TOML, then reads the sections in dependency order.
#include <set>

#include <fmt/format.h>

#include "scene/loader.hpp"
#include "scene/scene.hpp"
#include "scene/scene_text.hpp"

#include "core/input_file.hpp"

namespace tactus::scene {

namespace detail {

std::filesystem::path resolve_file(Reader& r, std::string_view key, const std::string& value) {
  const Context& ctx = r.context();
  if (!ctx.options.allow_file_access) r.fail(key, "file access is disabled; cannot read '" + value + "'");
  if (value.empty()) r.fail(key, "empty file name");
  std::filesystem::path p(value);
  if (p.is_relative() && !ctx.base_dir.empty()) p = ctx.base_dir / p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec)) r.fail(key, "file not found: '" + p.generic_string() + "'");
  return p;
}

namespace {

LoopRates read_rates(Reader& root) {
  LoopRates rates;
  if (auto r = root.table("rates")) {
    rates.haptic = r->number("haptic", rates.haptic, Range::closed(100.0, 10000.0));
    rates.simulation = r->number("simulation", rates.simulation, Range::closed(1.0, 1000.0));
    rates.interaction = r->number("interaction", rates.interaction, Range::closed(1.0, 1000.0));
    rates.visual = r->number("visual", rates.visual, Range::closed(1.0, 240.0));
    rates.catch_up = r->number("catch_up", rates.catch_up, Range::closed(1.0, 10.0));
    if (rates.simulation > rates.haptic)
      r->fail("simulation", fmt::format("{} Hz exceeds the haptic rate ({} Hz)", number_text(rates.simulation),
                                        number_text(rates.haptic)));
    r->finish();
  }
  return rates;
}

RealtimeSettings read_realtime(Reader& root, const LoopRates& rates) {
  RealtimeSettings rt;
  if (auto r = root.table("realtime")) {
    rt.priority = r->integer("priority", rt.priority, 0, 99);
    rt.haptic_cpu = r->integer("haptic_cpu", rt.haptic_cpu, -1, 1023);
    rt.spin = r->number("spin", rt.spin, Range::closed(0.0, 1.0 / rates.haptic));
    rt.dedicated_core = r->boolean("dedicated_core", rt.dedicated_core);
    r->finish();
  }
  return rt;
}

StaticSolve read_static_solve(Reader& root) {
  StaticSolve s;
  auto r = root.table("solve");
  if (!r) return s;
  s.newton.tolerance = r->number("tolerance", s.newton.tolerance, Range::open_closed(0.0, 1e-2));
  s.newton.force_tolerance = r->number("force_tolerance", s.newton.force_tolerance, Range::non_negative());
  s.newton.max_iterations = r->integer("max_iterations", s.newton.max_iterations, 1, 10000);
  s.max_step_halvings = r->integer("max_step_halvings", s.max_step_halvings, 0, 30);
  r->finish();
  return s;
}

Recording read_recording(Reader& root) {
  Recording rec;
  auto r = root.table("recording");
  if (!r) return rec;
  rec.path = r->string("path", "");
  const auto include = r->string_list("include", {"poses", "forces", "contacts", "timings", "events"});
  rec.poses = rec.forces = rec.contacts = rec.timings = rec.events = false;
  for (const auto& what : include) {
    bool* flag = what == "poses"      ? &rec.poses
                 : what == "forces"   ? &rec.forces
                 : what == "contacts" ? &rec.contacts
                 : what == "timings"  ? &rec.timings
                 : what == "events"   ? &rec.events
                                      : nullptr;
    if (!flag) {
      std::string msg = "unknown item '" + what + "'";
      if (const auto s = suggestion(what, {"poses", "forces", "contacts", "timings", "events"}); !s.empty())
        msg += "; " + s;
      r->fail("include", msg + " (expected poses, forces, contacts, timings or events)");
    }
    *flag = true;
  }
  r->finish();
  return rec;
}

Model read_model(Reader& root, const std::string& source_name) {
  Model m;
  m.source = source_name;
  m.name = std::filesystem::path(source_name).stem().string();
  if (auto s = root.table("scene")) {
    m.name = s->string("name", m.name);
    m.description = s->string("description", "");
    m.gravity = s->vec3("gravity", m.gravity);
    s->finish();
  }
  m.rates = read_rates(root);
  m.realtime = read_realtime(root, m.rates);

  // Sections in dependency order: each may refer to the ones before it.
  if (auto t = root.table("materials"))
    for (auto& [name, r] : t->named_tables()) m.materials.push_back(detail::read_material(r, name));
  // Cspace bodies that name their tools (a two-point space), resolved once the tools are read.
  std::vector<std::pair<std::size_t, Reader>> cspace_tools;
  if (auto t = root.table("bodies")) {
    // Embedded surfaces last: they name the body that carries them.
    std::vector<std::pair<std::string, Reader>> embedded;
    for (auto& [name, r] : t->named_tables()) {
      if (r.string("kind") == "embedded") {
        embedded.emplace_back(name, r);
        continue;
      }
      m.bodies.push_back(detail::read_body(r, name, m));
      if (m.bodies.back().cspace && r.has("tools")) cspace_tools.emplace_back(m.bodies.size() - 1, r);
    }
    for (auto& [name, r] : embedded) m.bodies.push_back(detail::read_body(r, name, m));
  }
  if (auto t = root.table("devices"))
    for (auto& [name, r] : t->named_tables()) m.devices.push_back(detail::read_device(r, name));
  if (auto t = root.table("tools"))
    for (auto& [name, r] : t->named_tables()) m.tools.push_back(detail::read_tool(r, name, m));
  for (auto& [body, r] : cspace_tools) detail::read_cspace_tools(r, m, body);
  if (auto t = root.table("algorithms")) {
    auto tables = t->named_tables();
    for (auto& [name, r] : tables) m.algorithms.push_back(detail::read_algorithm(r, name, m));
    for (std::size_t i = 0; i < tables.size(); ++i) detail::check_partner(tables[i].second, m, i);
  }
  m.recording = read_recording(root);
  m.feedback = detail::read_feedback(root);
  m.static_solve = read_static_solve(root);
  if (auto t = root.table("precompute")) m.precompute = detail::read_precompute(*t, m);
  m.level_selection = read_level_selection(root);
  root.finish();
  return m;
}

}  // namespace
}  // namespace detail

namespace {

/// A scene that names `[scene] base = "FILE"` is that file's scene with its own keys on top
/// (a scenario: the same patient, other devices). Bases may chain, at most 8 deep.
/// Arrays and inline tables nested deeper than this are refused before parsing: the TOML
/// parser recurses once per level, and a hundred thousand levels overflow its stack.
constexpr int kMaxNesting = 128;

/// Refuses text whose brackets and braces (outside strings and comments) nest deeper than
/// kMaxNesting, naming the line where it happens.
void check_nesting(std::string_view text, const std::string& source) {
  int depth = 0;
  std::uint64_t line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      // Strings, basic ("...", with escapes) or literal ('...'), single or triple quoted.
      const bool triple = text.substr(i, 3) == std::string(3, c);
      const std::string_view close = triple ? std::string_view(c == '"' ? "\"\"\"" : "'''") : std::string_view(&text[i], 1);
      i += triple ? 3 : 1;
      while (i < text.size() && text.substr(i, close.size()) != close) {
        if (text[i] == '\n') ++line;
        if (c == '"' && text[i] == '\\') ++i;  // an escaped character
        ++i;
      }
      i += close.size() - 1;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw InputError(SourceLocation{source, line, {}, {}},
                         "arrays and tables nested more than " + std::to_string(kMaxNesting) + " levels deep");
    } else if (c == ']' || c == '}') {
      depth = std::max(0, depth - 1);
    }
  }
}

void apply_base(toml::table& root, const detail::Context& ctx, int depth) {
  toml::table* scene = root["scene"].as_table();
  if (!scene || !scene->contains("base")) return;
  const toml::node& node = *scene->get("base");
  const auto name = node.value<std::string>();
  if (!name) throw InputError(detail::location(ctx, node.source()), "'scene.base' must be a file name (a string)");
  if (depth >= 8)
    throw InputError(detail::location(ctx, node.source()), "'scene.base' chains more than 8 scenes deep (a cycle?)");
  std::filesystem::path path(*name);
  if (path.is_relative()) path = ctx.base_dir / path;
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputError& e) {
    throw InputError(detail::location(ctx, node.source()), "base scene '" + path.string() + "': " + e.reason());
  }
  check_nesting(text, path.string());
  toml::table base;
  try {
    base = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(detail::location(ctx, e.source()), std::string(e.description()));
  }
  apply_base(base, ctx, depth + 1);
  scene->erase("base");
  merge_tables(base, root);
  root = std::move(base);
}

}  // namespace

namespace {

detail::Context context_of(const std::string& source_name, const LoadOptions& options) {
  detail::Context ctx;
  ctx.file = source_name;
  ctx.base_dir = options.base_dir.empty() ? std::filesystem::path(source_name).parent_path() : options.base_dir;
  ctx.options = options;
  return ctx;
}

/// The scene's TOML with its base chain merged in; parse errors located.
toml::table parse_with_base(std::string_view toml_text, const detail::Context& ctx) {
  check_nesting(toml_text, ctx.file);
  toml::table root;
  try {
    root = toml::parse(toml_text, ctx.file);
    apply_base(root, ctx, 0);
  } catch (const toml::parse_error& e) {
    throw InputError(detail::location(ctx, e.source()), std::string(e.description()));
  }
  return root;
}

}  // namespace

toml::table flatten_scene(std::string_view toml_text, const std::string& source_name, const LoadOptions& options) {
  return parse_with_base(toml_text, context_of(source_name, options));
}

Model parse_scene(std::string_view toml_text, const std::string& source_name, const LoadOptions& options) {
  const detail::Context ctx = context_of(source_name, options);
  toml::table root = parse_with_base(toml_text, ctx);
  detail::Reader reader(ctx, root, "");
  return detail::read_model(reader, source_name);
}

Model load_scene(const std::filesystem::path& path, const LoadOptions& options) {
  const std::string text = read_input_file(path);
  LoadOptions opts = options;
  if (opts.base_dir.empty()) opts.base_dir = path.parent_path();
  return parse_scene(text, path.string(), opts);
}

}  // namespace tactus::scene
