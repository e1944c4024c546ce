#pragma once
// The on-disk cache of impostor hierarchies: one binary file per object, named by the hash
// of its input mesh, holding the levels' meshes, errors and costs with the hash and the
// build parameters (docs/lod.md gives the layout byte by byte). A load restores each level's
// BVH and curvature from its mesh (deterministic), not the measured errors and costs, which
// come from the file. Any mismatch or damage is an InputError naming the file, the byte
// offset and the reason; the caller then rebuilds (load_or_build_impostors does).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lod/impostors.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::lod {

inline constexpr std::uint32_t kImpostorCacheVersion = 1;

/// What a cache file must have been built for.
struct CacheKey {
  std::uint64_t mesh_hash = 0;
  ImpostorParams params;
};

/// The file's bytes for a hierarchy.
[[nodiscard]] std::vector<std::uint8_t> encode_impostor_cache(const ImpostorHierarchy& hierarchy);

/// The hierarchy in `bytes` (`name` is the file named in errors). With `expected`, a file
/// built for another mesh hash or other parameters is refused. Throws InputError with the
/// byte offset for a bad magic or version, a count beyond the bytes left, an index out of
/// range, a non-finite value, a level that is not a closed outward surface, a checksum that
/// does not match or bytes after the end; never reads past the span.
[[nodiscard]] ImpostorHierarchy decode_impostor_cache(std::span<const std::uint8_t> bytes, const std::string& name,
                                                      const std::optional<CacheKey>& expected = std::nullopt);

/// `directory` / the hash as 16 hex digits + ".tlod".
[[nodiscard]] std::filesystem::path impostor_cache_path(const std::filesystem::path& directory,
                                                        std::uint64_t mesh_hash);

/// Writes the file through a temporary next to it, renamed over `path`, so a reader never
/// sees half a file. Throws InputError when the file cannot be written.
void save_impostor_cache(const std::filesystem::path& path, const ImpostorHierarchy& hierarchy);

/// The hierarchy cached at `path` for `input` and `params` (errors as decode_impostor_cache,
/// and a missing file).
[[nodiscard]] ImpostorHierarchy load_impostor_cache(const std::filesystem::path& path, const mesh::TriMesh& input,
                                                    const ImpostorParams& params);

/// The cached hierarchy from `directory` when its file matches; otherwise built and saved
/// there (the directory is created). `reason`, when given, receives why the cache was not
/// used (empty when it was).
[[nodiscard]] ImpostorHierarchy load_or_build_impostors(const std::filesystem::path& directory,
                                                        const mesh::TriMesh& input, const ImpostorParams& params,
                                                        std::string* reason = nullptr);

}  // namespace tactus::lod
