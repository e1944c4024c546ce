#pragma once
// Typed, located access to TOML tables for the scene loader and the other TOML inputs that
// share its messages (the experiment files of src/fitting); the only header that includes
// toml++. Every getter records its key as known, so that
// finish() can reject the keys nobody asked for and suggest the closest known one.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "core/error.hpp"
#include "core/math.hpp"
#include "scene/scene.hpp"

namespace tactus::scene::detail {

/// What one load shares: the name used in messages and where relative paths resolve.
struct Context {
  std::string file;
  std::filesystem::path base_dir;
  LoadOptions options;
};

/// An interval for a numeric key, with the wording of its error message.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range any() { return {}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range open(double a, double b) { return {a, b, true, true}; }
  static Range open_closed(double a, double b) { return {a, b, true, false}; }

  [[nodiscard]] bool contains(double v) const;
  [[nodiscard]] std::string describe() const;  ///< "must be > 0", "must be in (-1, 0.5)"
};

SourceLocation location(const Context& ctx, const toml::source_region& region);
[[noreturn]] void fail_at(const Context& ctx, const toml::source_region& region, const std::string& what);
std::string type_name(toml::node_type t);
/// The closest candidate within a small edit distance, or empty.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);
/// "did you mean 'x'?" text for a message, or empty.
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates);
/// Shortest text that reads back as the same double.
std::string number_text(double v);

class Reader {
 public:
  Reader(const Context& ctx, const toml::table& table, std::string path);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::string key_path(std::string_view key) const;
  [[nodiscard]] const Context& context() const { return *ctx_; }
  [[nodiscard]] const toml::table& table() const { return *table_; }

  /// The value under key (marking the key known), or nullptr.
  const toml::node* get(std::string_view key);
  bool has(std::string_view key) { return get(key) != nullptr; }

  std::optional<double> number(std::string_view key, const Range& range = Range::any());
  double number(std::string_view key, double fallback, const Range& range = Range::any());
  double required_number(std::string_view key, const Range& range = Range::any());

  std::optional<std::int64_t> integer(std::string_view key, std::int64_t lo, std::int64_t hi);
  int integer(std::string_view key, int fallback, int lo, int hi);

  std::optional<std::string> string(std::string_view key);
  std::string string(std::string_view key, std::string fallback);
  std::string required_string(std::string_view key);

  bool boolean(std::string_view key, bool fallback);

  std::optional<Vec3> vec3(std::string_view key);
  Vec3 vec3(std::string_view key, const Vec3& fallback);
  Vec3 required_vec3(std::string_view key);
  std::optional<Vec2> vec2(std::string_view key);
  Vec2 required_vec2(std::string_view key);

  std::optional<Reader> table(std::string_view key);
  /// An array of tables ([[key]] or key = [{...}, ...]); empty when absent.
  std::vector<Reader> table_array(std::string_view key);
  /// An array of strings; `fallback` when absent.
  std::vector<std::string> string_list(std::string_view key, std::vector<std::string> fallback);
  /// An array of numbers in `range`; empty when absent.
  std::vector<double> number_list(std::string_view key, const Range& range = Range::any());
  /// An array of integers in [lo, hi]; empty when absent.
  std::vector<std::int64_t> integer_list(std::string_view key, std::int64_t lo, std::int64_t hi);

  /// A string key restricted to `options` (name → value); `fallback` when absent.
  template <class E>
  E choice(std::string_view key, std::initializer_list<std::pair<std::string_view, E>> options,
           std::optional<E> fallback);

  /// Every entry of this table as a named sub-table, in file order (materials.*, bodies.*).
  std::vector<std::pair<std::string, Reader>> named_tables();

  /// Rejects keys that no getter asked for.
  void finish() const;

  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  [[noreturn]] void fail_here(const std::string& message) const;
  /// "missing required key 'key' (what)"; but when an unknown key in this table looks
  /// like a misspelling of it, reports that key instead (the real mistake).
  [[noreturn]] void fail_missing(std::string_view key, const std::string& what) const;
  /// Error at a node inside this table (an array element), with its own key path.
  [[noreturn]] void fail_node(const toml::node& node, const std::string& node_path,
                              const std::string& message) const;

 private:
  const toml::node* typed(std::string_view key, bool ok(const toml::node&), const char* expected);
  double checked_number(const toml::node& node, const std::string& node_path, const Range& range) const;

  const Context* ctx_;
  const toml::table* table_;
  std::string path_;
  std::set<std::string, std::less<>> known_;
};

/// A string value restricted to options, with a did-you-mean on mismatch.
template <class E>
E Reader::choice(std::string_view key, std::initializer_list<std::pair<std::string_view, E>> options,
                 std::optional<E> fallback) {
  const auto value = string(key);
  if (!value) {
    if (fallback) return *fallback;
    fail_missing(key, "a string");
  }
  std::vector<std::string> names;
  for (const auto& [name, e] : options) {
    if (name == *value) return e;
    names.emplace_back(name);
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  std::string msg = "unknown value '" + *value + "'";
  if (const auto s = suggestion(*value, names); !s.empty()) msg += "; " + s;
  fail(key, msg + " (expected one of: " + list + ")");
}

}  // namespace tactus::scene::detail
