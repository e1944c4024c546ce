#include "lod/impostor_cache.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/input_file.hpp"

namespace tactus::lod {
namespace {

constexpr std::uint8_t kMagic[8] = {'T', 'L', 'O', 'D', 'C', 'A', 'C', 'H'};

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  Fnv1a h;
  h.add(bytes.data(), bytes.size());
  return h.value();
}

struct Writer {
  std::vector<std::uint8_t> bytes;
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
};

/// A bounded cursor: every read checks the bytes left and throws with the offset.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  [[noreturn]] void fail(std::size_t offset, const std::string& why) const {
    throw InputError(SourceLocation{name_, std::nullopt, std::nullopt, offset}, "impostor cache: " + why);
  }
  [[nodiscard]] std::size_t offset() const { return at_; }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - at_; }

  void need(std::size_t n, const char* what) const {
    if (left() < n)
      fail(at_, std::string("truncated: ") + what + " needs " + std::to_string(n) + " bytes, " +
                    std::to_string(left()) + " left");
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(bytes_[at_ + static_cast<std::size_t>(i)]) << (8 * i);
    at_ += 4;
    return v;
  }
  std::uint64_t u64(const char* what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(bytes_[at_ + static_cast<std::size_t>(i)]) << (8 * i);
    at_ += 8;
    return v;
  }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  double f64(const char* what) { return std::bit_cast<double>(u64(what)); }
  /// A finite value ≥ 0 (errors, costs).
  double non_negative(const char* what) {
    const std::size_t where = at_;
    const double v = f64(what);
    if (!(std::isfinite(v) && v >= 0.0)) fail(where, std::string(what) + " is not a finite value ≥ 0");
    return v;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

/// The first parameter that differs, as "name: file vs wanted"; empty when none.
std::string params_difference(const ImpostorParams& file, const ImpostorParams& wanted) {
  const auto differs = [](const char* name, auto a, auto b) {
    return std::string(name) + " " + std::to_string(a) + " in the file, " + std::to_string(b) + " wanted";
  };
  if (file.coarse_levels != wanted.coarse_levels) return differs("coarse_levels", file.coarse_levels, wanted.coarse_levels);
  if (file.reduction != wanted.reduction) return differs("reduction", file.reduction, wanted.reduction);
  if (file.subdivision_levels != wanted.subdivision_levels)
    return differs("subdivision_levels", file.subdivision_levels, wanted.subdivision_levels);
  if (file.curvature_radius != wanted.curvature_radius)
    return differs("curvature_radius", file.curvature_radius, wanted.curvature_radius);
  if (file.error_samples != wanted.error_samples) return differs("error_samples", file.error_samples, wanted.error_samples);
  if (file.cost_queries != wanted.cost_queries) return differs("cost_queries", file.cost_queries, wanted.cost_queries);
  if (file.seed != wanted.seed) return differs("seed", file.seed, wanted.seed);
  return {};
}

}  // namespace

std::vector<std::uint8_t> encode_impostor_cache(const ImpostorHierarchy& h) {
  Writer w;
  // One byte at a time: GCC 12 at -O2 takes a range insert into the empty vector for an
  // overflow (-Wstringop-overflow, a false positive).
  for (const std::uint8_t b : kMagic) w.bytes.push_back(b);
  w.u32(kImpostorCacheVersion);
  w.u64(h.mesh_hash);
  w.i32(h.params.coarse_levels);
  w.f64(h.params.reduction);
  w.i32(h.params.subdivision_levels);
  w.f64(h.params.curvature_radius);
  w.i32(h.params.error_samples);
  w.i32(h.params.cost_queries);
  w.u64(h.params.seed);
  w.f64(h.curvature_radius);
  w.u32(static_cast<std::uint32_t>(h.levels.size()));
  w.u32(static_cast<std::uint32_t>(h.input_level));
  for (const ImpostorLevel& level : h.levels) {
    w.u32(static_cast<std::uint32_t>(level.mesh.vertices.size()));
    w.u32(static_cast<std::uint32_t>(level.mesh.triangles.size()));
    for (const Vec3& p : level.mesh.vertices)
      for (int k = 0; k < 3; ++k) w.f64(p[k]);
    for (const mesh::Triangle& t : level.mesh.triangles)
      for (const mesh::Index i : t) w.i32(i);
    w.f64(level.error.hausdorff);
    w.f64(level.error.curvature_rms);
    w.f64(level.cost.query_p50);
    w.f64(level.cost.query_p99);
    w.f64(level.cost.build_time);
  }
  w.u64(fnv1a(w.bytes));
  return std::move(w.bytes);
}

ImpostorHierarchy decode_impostor_cache(std::span<const std::uint8_t> bytes, const std::string& name,
                                        const std::optional<CacheKey>& expected) {
  Reader r(bytes, name);
  r.need(sizeof kMagic, "the magic");
  for (std::size_t i = 0; i < sizeof kMagic; ++i)
    if (bytes[i] != kMagic[i]) r.fail(0, "not an impostor cache file (no TLODCACH magic)");
  (void)r.u64("the magic");
  const std::size_t version_at = r.offset();
  const std::uint32_t version = r.u32("the version");
  if (version != kImpostorCacheVersion)
    r.fail(version_at, "version " + std::to_string(version) + ", this build reads version " +
                           std::to_string(kImpostorCacheVersion));

  ImpostorHierarchy h;
  const std::size_t hash_at = r.offset();
  h.mesh_hash = r.u64("the mesh hash");
  const std::size_t params_at = r.offset();
  h.params.coarse_levels = r.i32("coarse_levels");
  h.params.reduction = r.f64("reduction");
  h.params.subdivision_levels = r.i32("subdivision_levels");
  h.params.curvature_radius = r.f64("curvature_radius");
  h.params.error_samples = r.i32("error_samples");
  h.params.cost_queries = r.i32("cost_queries");
  h.params.seed = r.u64("seed");
  if (expected) {
    if (h.mesh_hash != expected->mesh_hash)
      r.fail(hash_at, "built for another mesh (hash " + hex(h.mesh_hash) + ", this mesh " + hex(expected->mesh_hash) + ")");
    const std::string difference = params_difference(h.params, expected->params);
    if (!difference.empty()) r.fail(params_at, "built with other parameters: " + difference);
  }
  try {
    check_params(h.params);
  } catch (const InputError& e) {
    r.fail(params_at, e.reason());
  }
  const std::size_t radius_at = r.offset();
  h.curvature_radius = r.f64("the curvature radius");
  if (!(std::isfinite(h.curvature_radius) && h.curvature_radius > 0.0))
    r.fail(radius_at, "the curvature radius is not a finite value > 0");

  const std::size_t count_at = r.offset();
  const std::uint32_t level_count = r.u32("the level count");
  const std::uint32_t input_level = r.u32("the input level");
  const auto wanted_levels = static_cast<std::uint32_t>(h.params.coarse_levels + 1 + h.params.subdivision_levels);
  if (level_count != wanted_levels || input_level != static_cast<std::uint32_t>(h.params.coarse_levels))
    r.fail(count_at, std::to_string(level_count) + " levels with the input at " + std::to_string(input_level) +
                         "; the parameters make " + std::to_string(wanted_levels) + " with the input at " +
                         std::to_string(h.params.coarse_levels));
  h.input_level = input_level;
  h.levels.resize(level_count);
  for (std::uint32_t l = 0; l < level_count; ++l) {
    ImpostorLevel& level = h.levels[l];
    const std::size_t level_at = r.offset();
    const std::uint32_t vertices = r.u32("a vertex count");
    const std::uint32_t triangles = r.u32("a triangle count");
    // Counts are checked against the bytes left before anything is allocated.
    r.need(static_cast<std::size_t>(vertices) * 24 + static_cast<std::size_t>(triangles) * 12,
           "a level's vertices and triangles");
    level.mesh.vertices.resize(vertices);
    for (Vec3& p : level.mesh.vertices) {
      const std::size_t at = r.offset();
      for (int k = 0; k < 3; ++k) p[k] = r.f64("a coordinate");
      if (!p.allFinite()) r.fail(at, "a vertex of level " + std::to_string(l) + " is not finite");
    }
    level.mesh.triangles.resize(triangles);
    for (mesh::Triangle& t : level.mesh.triangles) {
      const std::size_t at = r.offset();
      for (mesh::Index& i : t) {
        i = r.i32("a vertex index");
        if (i < 0 || static_cast<std::uint32_t>(i) >= vertices)
          r.fail(at, "a triangle of level " + std::to_string(l) + " names vertex " + std::to_string(i) + " of " +
                         std::to_string(vertices));
      }
    }
    level.error.hausdorff = r.non_negative("a Hausdorff distance");
    level.error.curvature_rms = r.non_negative("a curvature error");
    level.cost.query_p50 = r.non_negative("a query time");
    level.cost.query_p99 = r.non_negative("a query time");
    level.cost.build_time = r.non_negative("a build time");
    try {
      check_closed_surface(level.mesh, "level " + std::to_string(l));
    } catch (const InputError& e) {
      r.fail(level_at, e.reason());
    }
    if (l == input_level && level.mesh.content_hash() != h.mesh_hash)
      r.fail(level_at, "the input level does not hash to the file's mesh hash");
  }
  const std::size_t checksum_at = r.offset();
  const std::uint64_t checksum = r.u64("the checksum");
  if (checksum != fnv1a(bytes.first(checksum_at))) r.fail(checksum_at, "checksum mismatch: the file is damaged");
  if (r.left() != 0) r.fail(r.offset(), std::to_string(r.left()) + " bytes after the end");
  for (ImpostorLevel& level : h.levels) {
    const LevelCost measured = level.cost;
    prepare_level(level, h.curvature_radius);
    level.cost.query_p50 = measured.query_p50;
    level.cost.query_p99 = measured.query_p99;
    level.cost.build_time = measured.build_time;
  }
  return h;
}

std::filesystem::path impostor_cache_path(const std::filesystem::path& directory, std::uint64_t hash) {
  return directory / (hex(hash) + ".tlod");
}

void save_impostor_cache(const std::filesystem::path& path, const ImpostorHierarchy& hierarchy) {
  const std::vector<std::uint8_t> bytes = encode_impostor_cache(hierarchy);
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw InputError(SourceLocation{temporary.string(), {}, {}, {}}, "cannot write the impostor cache");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error)
    throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot write the impostor cache: " + error.message());
}

ImpostorHierarchy load_impostor_cache(const std::filesystem::path& path, const mesh::TriMesh& input,
                                      const ImpostorParams& params) {
  if (!std::filesystem::exists(path))
    throw InputError(SourceLocation{path.string(), {}, {}, {}}, "impostor cache: no such file");
  const std::string text = read_input_file(path);
  const auto* data = reinterpret_cast<const std::uint8_t*>(text.data());
  return decode_impostor_cache(std::span<const std::uint8_t>(data, text.size()), path.string(),
                               CacheKey{input.content_hash(), params});
}

ImpostorHierarchy load_or_build_impostors(const std::filesystem::path& directory, const mesh::TriMesh& input,
                                          const ImpostorParams& params, std::string* reason) {
  const std::filesystem::path path = impostor_cache_path(directory, input.content_hash());
  try {
    ImpostorHierarchy cached = load_impostor_cache(path, input, params);
    if (reason) reason->clear();
    return cached;
  } catch (const InputError& e) {
    if (reason) *reason = e.what();
  }
  ImpostorHierarchy built = build_impostors(input, params);
  std::filesystem::create_directories(directory);
  save_impostor_cache(path, built);
  return built;
}

}  // namespace tactus::lod
