#include "scene/toml_reader.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tactus::scene::detail {

bool Range::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo);
  const bool has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    return fmt::format("must be in {}{}, {}{}", lo_open ? "(" : "[", number_text(lo), number_text(hi),
                       hi_open ? ")" : "]");
  if (has_lo) return fmt::format("must be {} {}", lo_open ? ">" : ">=", number_text(lo));
  if (has_hi) return fmt::format("must be {} {}", hi_open ? "<" : "<=", number_text(hi));
  return "must be finite";
}

std::string number_text(double v) {
  // Integral values print without a trailing ".0" so messages read like the file.
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15) return fmt::format("{}", static_cast<long long>(v));
  return fmt::format("{}", v);
}

SourceLocation location(const Context& ctx, const toml::source_region& region) {
  SourceLocation loc;
  loc.file = ctx.file;
  // A key inherited from a base scene ([scene] base) is located in that file.
  if (region.path && !region.path->empty()) loc.file = *region.path;
  if (region.begin.line > 0) {
    loc.line = region.begin.line;
    if (region.begin.column > 0) loc.column = region.begin.column;
  }
  return loc;
}

void fail_at(const Context& ctx, const toml::source_region& region, const std::string& what) {
  throw InputError(location(ctx, region), what);
}

std::string type_name(toml::node_type t) {
  switch (t) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a floating-point number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

bool is_integer(const toml::node& n) { return n.is_integer(); }
bool is_string(const toml::node& n) { return n.is_string(); }
bool is_boolean(const toml::node& n) { return n.is_boolean(); }
bool is_table(const toml::node& n) { return n.is_table(); }
bool is_array(const toml::node& n) { return n.is_array(); }

}  // namespace

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  // Close enough to be a typo: two edits, or a third of the word for long keys.
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  return best_d <= limit ? best : std::string();
}

std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string c = closest(word, candidates);
  return c.empty() ? c : "did you mean '" + c + "'?";
}

Reader::Reader(const Context& ctx, const toml::table& table, std::string path)
    : ctx_(&ctx), table_(&table), path_(std::move(path)) {}

std::string Reader::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void Reader::fail(std::string_view key, const std::string& message) const {
  if (const toml::node* n = table_->get(key)) fail_at(*ctx_, n->source(), key_path(key) + ": " + message);
  fail_here(message);
}

void Reader::fail_here(const std::string& message) const {
  fail_at(*ctx_, table_->source(), path_.empty() ? message : path_ + ": " + message);
}

void Reader::fail_missing(std::string_view key, const std::string& what) const {
  for (const auto& [k, v] : *table_) {
    if (known_.count(k.str()) || closest(k.str(), {std::string(key)}).empty()) continue;
    fail_at(*ctx_, k.source(),
            key_path(k.str()) + ": unknown key '" + std::string(k.str()) + "'; did you mean '" + std::string(key) + "'?");
  }
  fail_here("missing required key '" + std::string(key) + "' (" + what + ")");
}

void Reader::fail_node(const toml::node& node, const std::string& node_path, const std::string& message) const {
  fail_at(*ctx_, node.source(), node_path + ": " + message);
}

const toml::node* Reader::get(std::string_view key) {
  known_.emplace(key);
  return table_->get(key);
}

const toml::node* Reader::typed(std::string_view key, bool ok(const toml::node&), const char* expected) {
  const toml::node* n = get(key);
  if (n && !ok(*n)) fail(key, std::string("expected ") + expected + ", got " + type_name(n->type()));
  return n;
}

double Reader::checked_number(const toml::node& node, const std::string& node_path, const Range& range) const {
  if (!node.is_number()) fail_node(node, node_path, "expected a number, got " + type_name(node.type()));
  const double v = node.value<double>().value_or(0.0);
  if (!std::isfinite(v)) fail_node(node, node_path, "expected a finite number, got " + number_text(v));
  if (!range.contains(v)) fail_node(node, node_path, number_text(v) + " is out of range: " + range.describe());
  return v;
}

std::optional<double> Reader::number(std::string_view key, const Range& range) {
  const toml::node* n = get(key);
  if (!n) return std::nullopt;
  return checked_number(*n, key_path(key), range);
}

double Reader::number(std::string_view key, double fallback, const Range& range) {
  return number(key, range).value_or(fallback);
}

double Reader::required_number(std::string_view key, const Range& range) {
  if (auto v = number(key, range)) return *v;
  fail_missing(key, "a number");
}

std::optional<std::int64_t> Reader::integer(std::string_view key, std::int64_t lo, std::int64_t hi) {
  const toml::node* n = typed(key, is_integer, "an integer");
  if (!n) return std::nullopt;
  const std::int64_t v = n->value<std::int64_t>().value_or(0);
  if (v < lo || v > hi) fail(key, fmt::format("{} is out of range: must be in [{}, {}]", v, lo, hi));
  return v;
}

int Reader::integer(std::string_view key, int fallback, int lo, int hi) {
  return static_cast<int>(integer(key, std::int64_t{lo}, std::int64_t{hi}).value_or(fallback));
}

std::optional<std::string> Reader::string(std::string_view key) {
  const toml::node* n = typed(key, is_string, "a string");
  if (!n) return std::nullopt;
  return std::string(n->value<std::string_view>().value_or(""));
}

std::string Reader::string(std::string_view key, std::string fallback) {
  return string(key).value_or(std::move(fallback));
}

std::string Reader::required_string(std::string_view key) {
  if (auto v = string(key)) return *v;
  fail_missing(key, "a string");
}

bool Reader::boolean(std::string_view key, bool fallback) {
  const toml::node* n = typed(key, is_boolean, "a boolean");
  return n ? n->value<bool>().value_or(fallback) : fallback;
}

namespace {

template <int N>
Eigen::Matrix<double, N, 1> read_vector(const Reader& r, const toml::node& node, const std::string& path) {
  const toml::array* a = node.as_array();
  if (!a) r.fail_node(node, path, fmt::format("expected an array of {} numbers, got {}", N, type_name(node.type())));
  if (a->size() != static_cast<std::size_t>(N))
    r.fail_node(node, path, fmt::format("expected an array of {} numbers, got {} element{}", N, a->size(),
                                        a->size() == 1 ? "" : "s"));
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) {
    const toml::node& e = *a->get(static_cast<std::size_t>(i));
    const std::string ep = fmt::format("{}[{}]", path, i);
    if (!e.is_number()) r.fail_node(e, ep, "expected a number, got " + type_name(e.type()));
    v[i] = e.value<double>().value_or(0.0);
    if (!std::isfinite(v[i])) r.fail_node(e, ep, "expected a finite number, got " + number_text(v[i]));
  }
  return v;
}

}  // namespace

std::optional<Vec3> Reader::vec3(std::string_view key) {
  const toml::node* n = get(key);
  if (!n) return std::nullopt;
  return read_vector<3>(*this, *n, key_path(key));
}

Vec3 Reader::vec3(std::string_view key, const Vec3& fallback) { return vec3(key).value_or(fallback); }

Vec3 Reader::required_vec3(std::string_view key) {
  if (auto v = vec3(key)) return *v;
  fail_missing(key, "an array of 3 numbers");
}

std::optional<Vec2> Reader::vec2(std::string_view key) {
  const toml::node* n = get(key);
  if (!n) return std::nullopt;
  return read_vector<2>(*this, *n, key_path(key));
}

Vec2 Reader::required_vec2(std::string_view key) {
  if (auto v = vec2(key)) return *v;
  fail_missing(key, "an array of 2 numbers");
}

std::optional<Reader> Reader::table(std::string_view key) {
  const toml::node* n = typed(key, is_table, "a table");
  if (!n) return std::nullopt;
  return Reader(*ctx_, *n->as_table(), key_path(key));
}

std::vector<Reader> Reader::table_array(std::string_view key) {
  const toml::node* n = typed(key, is_array, "an array of tables");
  std::vector<Reader> out;
  if (!n) return out;
  const toml::array& a = *n->as_array();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const toml::node& e = *a.get(i);
    const std::string ep = fmt::format("{}[{}]", key_path(key), i);
    if (!e.is_table()) fail_node(e, ep, "expected a table, got " + type_name(e.type()));
    out.emplace_back(*ctx_, *e.as_table(), ep);
  }
  return out;
}

std::vector<std::string> Reader::string_list(std::string_view key, std::vector<std::string> fallback) {
  const toml::node* n = typed(key, is_array, "an array of strings");
  if (!n) return fallback;
  std::vector<std::string> out;
  const toml::array& a = *n->as_array();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const toml::node& e = *a.get(i);
    if (!e.is_string())
      fail_node(e, fmt::format("{}[{}]", key_path(key), i), "expected a string, got " + type_name(e.type()));
    out.emplace_back(e.value<std::string_view>().value_or(""));
  }
  return out;
}

std::vector<double> Reader::number_list(std::string_view key, const Range& range) {
  const toml::node* n = typed(key, is_array, "an array of numbers");
  std::vector<double> out;
  if (!n) return out;
  const toml::array& a = *n->as_array();
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(checked_number(*a.get(i), fmt::format("{}[{}]", key_path(key), i), range));
  return out;
}

std::vector<std::int64_t> Reader::integer_list(std::string_view key, std::int64_t lo, std::int64_t hi) {
  const toml::node* n = typed(key, is_array, "an array of integers");
  std::vector<std::int64_t> out;
  if (!n) return out;
  const toml::array& a = *n->as_array();
  out.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const toml::node& e = *a.get(i);
    const std::string ep = fmt::format("{}[{}]", key_path(key), i);
    if (!e.is_integer()) fail_node(e, ep, "expected an integer, got " + type_name(e.type()));
    const std::int64_t v = e.value<std::int64_t>().value_or(0);
    if (v < lo || v > hi) fail_node(e, ep, fmt::format("{} is out of range: must be in [{}, {}]", v, lo, hi));
    out.push_back(v);
  }
  return out;
}

std::vector<std::pair<std::string, Reader>> Reader::named_tables() {
  struct Entry {
    const toml::key* key;
    const toml::node* node;
  };
  std::vector<Entry> entries;
  for (const auto& [k, v] : *table_) entries.push_back({&k, &v});
  // toml++ keeps keys sorted; the file's order is what users expect to see back.
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    const auto& pa = a.key->source().begin;
    const auto& pb = b.key->source().begin;
    return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
  });
  std::vector<std::pair<std::string, Reader>> out;
  for (const Entry& e : entries) {
    const std::string name(e.key->str());
    known_.insert(name);
    const std::string p = key_path(name);
    if (!e.node->is_table()) fail_node(*e.node, p, "expected a table, got " + type_name(e.node->type()));
    const bool valid_name = !name.empty() && name.size() <= 64 &&
                            std::all_of(name.begin(), name.end(), [](char c) {
                              return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                     (c >= '0' && c <= '9') || c == '_' || c == '-';
                            });
    if (!valid_name)
      fail_at(*ctx_, e.key->source(),
              p + ": invalid name '" + name + "': use 1 to 64 letters, digits, '_' or '-'");
    out.emplace_back(name, Reader(*ctx_, *e.node->as_table(), p));
  }
  return out;
}

void Reader::finish() const {
  for (const auto& [k, v] : *table_) {
    if (known_.count(k.str())) continue;
    const std::vector<std::string> candidates(known_.begin(), known_.end());
    std::string msg = key_path(k.str()) + ": unknown key '" + std::string(k.str()) + "'";
    if (const auto s = suggestion(k.str(), candidates); !s.empty()) msg += "; " + s;
    fail_at(*ctx_, k.source(), msg);
  }
}

}  // namespace tactus::scene::detail
