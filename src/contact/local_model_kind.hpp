#pragma once
// Which local model bridges the haptic and simulation rates (docs/runtime.md); a small header
// of its own, so that the scene's model can name it without the models themselves.
#include <cstdint>

namespace tactus::contact {

enum class LocalModelKind : std::uint8_t {
  plane,        ///< a contact plane through the closest point (built by the interaction loop)
  compliance,   ///< condensed compliance of the patch nodes
  mass_spring,  ///< local mass-spring patch with a border at constant velocity
};

/// "plane", "compliance", "mass_spring".
[[nodiscard]] const char* local_model_name(LocalModelKind kind);

}  // namespace tactus::contact
