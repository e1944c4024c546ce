#include "scene/scene_text.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace tactus::scene {
namespace {

bool bare(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

void write_key(std::ostream& out, std::string_view key) {
  if (bare(key))
    out << key;
  else
    out << toml::toml_formatter{toml::value<std::string>(std::string(key))};
}

/// A key's place as the loader orders it (toml_reader.cpp, named_tables); none: last.
std::pair<std::uint64_t, std::uint64_t> place(const toml::key& key) {
  const auto& at = key.source().begin;
  if (at.line == 0) return {std::numeric_limits<std::uint64_t>::max(), 0};
  return {at.line, at.column};
}

void write_table(std::ostream& out, const toml::table& table, const std::string& path) {
  std::vector<std::pair<const toml::key*, const toml::node*>> values, tables;
  for (const auto& [key, node] : table) (node.is_table() ? tables : values).emplace_back(&key, &node);
  auto by_place = [](const auto& a, const auto& b) { return place(*a.first) < place(*b.first); };
  std::stable_sort(values.begin(), values.end(), by_place);
  std::stable_sort(tables.begin(), tables.end(), by_place);
  for (const auto& [key, node] : values) {
    write_key(out, key->str());
    out << " = ";
    // An array (of tables too) inline, as toml++ writes a value on its own.
    node->visit([&](const auto& v) { out << toml::toml_formatter{v}; });
    out << "\n";
  }
  for (const auto& [key, node] : tables) {
    std::ostringstream name;
    if (!path.empty()) name << path << ".";
    write_key(name, key->str());
    out << "\n[" << name.str() << "]\n";
    write_table(out, *node->as_table(), name.str());
  }
}

}  // namespace

void merge_tables(toml::table& base, const toml::table& over) {
  for (auto&& [key, node] : over) {
    const toml::table* over_table = node.as_table();
    toml::table* base_table = base[key].as_table();
    if (over_table && base_table)
      merge_tables(*base_table, *over_table);
    else
      base.insert_or_assign(key, node);
  }
}

std::string format_scene(const toml::table& root) {
  std::ostringstream out;
  write_table(out, root, "");
  return out.str();
}

}  // namespace tactus::scene
