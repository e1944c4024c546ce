#include "contact/grasp_state.hpp"

namespace tactus::contact {

ContactState classify(const ContactInputs& in) noexcept {
  const int on_fabric = (in.thumb_on_fabric ? 1 : 0) + (in.index_on_fabric ? 1 : 0);
  const bool slip = in.dynamic_friction;
  if (in.fingers_touch) {
    if (on_fabric == 0) return slip ? ContactState::III : ContactState::II;
    return slip ? ContactState::IX : ContactState::VIII;  // one contact: see the header
  }
  switch (on_fabric) {
    case 0:
      return ContactState::I;
    case 1:
      return slip ? ContactState::V : ContactState::IV;
    default:
      return slip ? ContactState::VII : ContactState::VI;
  }
}

bool is_possible(const ContactInputs& in) noexcept {
  return !(in.fingers_touch && in.thumb_on_fabric != in.index_on_fabric);
}

std::string_view name(ContactState state) noexcept {
  switch (state) {
    case ContactState::I: return "I";
    case ContactState::II: return "II";
    case ContactState::III: return "III";
    case ContactState::IV: return "IV";
    case ContactState::V: return "V";
    case ContactState::VI: return "VI";
    case ContactState::VII: return "VII";
    case ContactState::VIII: return "VIII";
    case ContactState::IX: return "IX";
  }
  return "?";
}

std::string_view describe(ContactState state) noexcept {
  switch (state) {
    case ContactState::I: return "no contact";
    case ContactState::II: return "fingers touch each other, static friction";
    case ContactState::III: return "fingers touch each other, dynamic friction";
    case ContactState::IV: return "one finger on the fabric, static friction";
    case ContactState::V: return "one finger on the fabric, dynamic friction";
    case ContactState::VI: return "both fingers on the fabric, static friction";
    case ContactState::VII: return "both fingers on the fabric, dynamic friction";
    case ContactState::VIII: return "fabric squeezed between the fingers, static friction";
    case ContactState::IX: return "fabric squeezed between the fingers, dynamic friction";
  }
  return "unknown";
}

}  // namespace tactus::contact
