#pragma once
// Configuration spaces in HDF5 files (layout: docs/precompute.md).
#include <filesystem>
#include <vector>

#include "precompute/space.hpp"

namespace tactus::precompute {

/// Writes `space` to `path` (through a temporary file renamed into place, so a reader never
/// sees half a file). Throws InputError when the file cannot be written.
void write_space(const std::filesystem::path& path, const Space& space);

/// Writes a space's levels in level order: a point space's one, or a probe or two-point
/// space's (level 0 at the root, as a point space is; the others in group `levels`).
void write_space_levels(const std::filesystem::path& path, const std::vector<Space>& levels);

/// Reads every level of a space: one for a point space, a probe space's leans, a two-point
/// space's 2 + nA + nB (precompute/pair.hpp).
/// Throws InputError for a missing, unreadable or malformed file or a missing level.
std::vector<Space> read_space_levels(const std::filesystem::path& path);

/// Reads a space (a probe or two-point space's level 0). Throws InputError for a missing, unreadable or malformed file.
Space read_space(const std::filesystem::path& path);

/// Reads a space and checks it against `model` (the identity of the body it is meant
/// for): throws InputError naming the difference when it was built for another mesh or
/// other settings.
Space load_space(const std::filesystem::path& path, const ModelIdentity& model);

}  // namespace tactus::precompute
