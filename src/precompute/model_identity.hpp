#pragma once
// What ties a configuration space to its model: FNV-1a hashes of the mesh (rest positions
// and elements) and of everything else a configuration depends on (material, fixed dofs,
// contact patch, grid and solver settings).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/hash.hpp"
#include "physics/body.hpp"
#include "precompute/grid.hpp"
#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

using tactus::Fnv1a;

/// 16 hexadecimal digits.
std::string hash_text(std::uint64_t h);

/// The identity of `body` (as the scene builds it, before the solver adds the patch) with
/// these settings and grid.
ModelIdentity identify(const physics::Body& body, const SpaceSettings& settings, const Grid& grid);

/// Throws InputError (located at `space_file`) when `space` was built for another model:
/// another mesh (node count or geometry), or the same mesh with other settings.
void check_identity(const ModelIdentity& space, const ModelIdentity& model, const std::string& space_file);

}  // namespace tactus::precompute
