#pragma once
// The contact states of a two-finger fabric interaction (seed 002 Table I), and which model
// renders each: I no force; II/III finger on finger (finger_contact.hpp); IV–VII the
// V-proxy on each touching finger (fabric_proxy.hpp); VIII/IX the two-finger grasp
// (grasp.hpp). Even numerals past I are static friction, odd ones dynamic.
#include <cstdint>
#include <string_view>

namespace tactus::contact {

enum class ContactState : std::uint8_t {
  I = 1,  ///< no contact: zero force
  II,     ///< fingers touch each other, no fabric; static friction
  III,    ///< fingers touch each other, no fabric; dynamic friction
  IV,     ///< one finger on the fabric; static
  V,      ///< one finger on the fabric; dynamic
  VI,     ///< both fingers on the fabric, apart; static
  VII,    ///< both fingers on the fabric, apart; dynamic
  VIII,   ///< fabric squeezed between the fingers; static
  IX,     ///< fabric squeezed between the fingers; dynamic
};

struct ContactInputs {
  bool thumb_on_fabric = false;
  bool index_on_fabric = false;
  /// The fingers touch each other, directly or with the fabric squeezed between them.
  bool fingers_touch = false;
  bool dynamic_friction = false;  ///< any touching contact slips
};

/// Table I. With no contact at all, friction plays no part: always I. The table's "-" (the
/// fingers touch and exactly one touches the fabric) cannot happen in the seed's setup (the
/// thumb only reaches the fabric's front, the index its back, and they touch by their pads),
/// so such inputs mean a fabric contact missed on the other finger while the fabric is
/// squeezed: classify() returns VIII or IX, the grasp, for them. is_possible() tells them
/// apart.
[[nodiscard]] ContactState classify(const ContactInputs& inputs) noexcept;

/// False for the table's "-" combination.
[[nodiscard]] bool is_possible(const ContactInputs& inputs) noexcept;

/// The Roman numeral, e.g. "VIII".
[[nodiscard]] std::string_view name(ContactState state) noexcept;
/// A short description, e.g. "fabric squeezed between the fingers, static friction".
[[nodiscard]] std::string_view describe(ContactState state) noexcept;

}  // namespace tactus::contact
