#pragma once
// The UDP bridge protocol, version 1 (docs/network-protocol.md): fixed-size little-endian
// packets, a pose from the driver and a force back, each closed by a CRC-32. Encoding and
// decoding are pure functions that never throw and never read outside the given bytes;
// PoseReceiver is the socket-free rule book that decides which pose is the newest.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>

#include "core/clock.hpp"
#include "core/math.hpp"
#include "haptics/device.hpp"

namespace tactus::haptics {

inline constexpr std::uint16_t kProtocolVersion = 1;
inline constexpr std::size_t kPosePacketSize = 84;
inline constexpr std::size_t kForcePacketSize = 80;
/// A pose whose quaternion norm differs from 1 by more than this is corrupt, not rounded.
inline constexpr double kQuaternionNormTolerance = 1e-2;
/// No handle moves this far from its origin [m]; larger coordinates are corrupt.
inline constexpr double kMaxPositionMagnitude = 100.0;

/// Bits of ForcePacket::flags: why the force may differ from what the contact asked for.
/// Bits 0–4 carry the safety layer's flags (haptics/safety.hpp, same values), so its
/// output passes through unchanged; bit 8 is the device's own.
enum ForceFlag : std::uint32_t {
  kForceClamped = 1u << 0,        ///< force or torque clamped to the device's limit
  kForceNonFinite = 1u << 1,      ///< a NaN or infinity was replaced by zero
  kForceRamping = 1u << 2,        ///< the force is ramping in or out
  kForceWatchdog = 1u << 3,       ///< simulation stalled or device not alive: fading out
  kForceEmergencyStop = 1u << 4,  ///< emergency stop latched
  kForceLinkTimeout = 1u << 8,    ///< no valid pose within the timeout (set by the device)
};

/// Driver → Tactus.
struct PosePacket {
  std::uint16_t device_index = 0;
  std::uint32_t sequence = 0;
  std::uint64_t timestamp_ns = 0;  ///< driver clock
  Vec3 position = Vec3::Zero();    ///< device coordinates [m]
  Quat orientation = Quat::Identity();
  std::uint32_t buttons = 0;
};

/// Tactus → driver.
struct ForcePacket {
  std::uint16_t device_index = 0;
  std::uint32_t sequence = 0;       ///< Tactus's own counter
  std::uint32_t pose_sequence = 0;  ///< the pose this force answers
  std::uint64_t timestamp_ns = 0;   ///< Tactus clock
  Vec3 force = Vec3::Zero();        ///< device coordinates [N]
  Vec3 torque = Vec3::Zero();       ///< [N·m]
  std::uint32_t flags = 0;          ///< ForceFlag bits
};

enum class PacketError : std::uint8_t {
  wrong_size,      ///< shorter than the header, or not the size of its version
  bad_magic,       ///< not "TPOS" / "TFRC"
  bad_version,     ///< a version this build does not speak
  bad_checksum,    ///< CRC-32 mismatch: corrupted in transit
  non_finite,      ///< NaN or infinity in a number
  bad_quaternion,  ///< orientation norm far from 1
  out_of_range,    ///< a position coordinate beyond kMaxPositionMagnitude
};
inline constexpr std::size_t kPacketErrorCount = 7;
static_assert(static_cast<std::size_t>(PacketError::out_of_range) + 1 == kPacketErrorCount);
[[nodiscard]] const char* to_string(PacketError error);

/// Either a packet or the reason it was refused.
template <class Packet>
class DecodeResult {
 public:
  // Implicit, so a decoder simply returns a packet or an error.
  DecodeResult(const Packet& packet) : value_(packet) {}
  DecodeResult(PacketError error) : value_(error) {}
  [[nodiscard]] bool ok() const { return std::holds_alternative<Packet>(value_); }
  /// Only when ok().
  [[nodiscard]] const Packet& packet() const { return std::get<Packet>(value_); }
  /// Only when !ok().
  [[nodiscard]] PacketError error() const { return std::get<PacketError>(value_); }

 private:
  std::variant<Packet, PacketError> value_;
};

/// Non-finite values are encoded as given: the receiver's decoder refuses them.
[[nodiscard]] std::array<std::byte, kPosePacketSize> encode(const PosePacket& packet);
[[nodiscard]] std::array<std::byte, kForcePacketSize> encode(const ForcePacket& packet);
[[nodiscard]] DecodeResult<PosePacket> decode_pose(std::span<const std::byte> bytes);
[[nodiscard]] DecodeResult<ForcePacket> decode_force(std::span<const std::byte> bytes);

struct ReceiverConfig {
  std::uint16_t device_index = 0;   ///< poses for other devices are counted and ignored
  Nanos timeout = 50'000'000;       ///< not alive after this long without a valid pose
  Nanos stale_after = 50'000'000;   ///< largest extra delay over the newest pose
};

struct ReceiverCounters {
  std::uint64_t datagrams = 0;  ///< everything offered to on_datagram
  std::uint64_t accepted = 0;   ///< became the newest pose
  std::array<std::uint64_t, kPacketErrorCount> malformed{};  ///< by PacketError
  std::uint64_t wrong_device = 0;
  std::uint64_t out_of_order = 0;  ///< sequence not after the newest (duplicates included)
  std::uint64_t stale = 0;         ///< timestamp backwards, or delayed beyond stale_after
  std::uint64_t resyncs = 0;       ///< accepted after a silence without ordering checks

  [[nodiscard]] std::uint64_t malformed_by(PacketError e) const {
    return malformed[static_cast<std::size_t>(e)];
  }
  [[nodiscard]] std::uint64_t malformed_total() const;
};

/// Keeps the newest valid pose from a stream of datagrams. Rules, in order: a datagram
/// that does not decode is malformed; another device index is wrong_device; then, while
/// alive, a sequence not after the newest (serial-number arithmetic, so 0 follows
/// 0xFFFFFFFF) is out_of_order, and a driver timestamp before the newest, or one that
/// arrives more than stale_after later than the newest did relative to the driver clock,
/// is stale. After `timeout` of silence the next valid pose is accepted unconditionally
/// (a restarted driver begins again at sequence 0). Arrival times never decrease.
class PoseReceiver {
 public:
  explicit PoseReceiver(ReceiverConfig config = {});

  /// Returns true when the datagram became the newest pose.
  bool on_datagram(std::span<const std::byte> datagram, Nanos arrival);
  /// A valid pose arrived within the timeout before `now`.
  [[nodiscard]] bool alive(Nanos now) const;
  [[nodiscard]] bool has_pose() const { return has_pose_; }
  /// The newest accepted packet (meaningful once has_pose()).
  [[nodiscard]] const PosePacket& newest() const { return newest_; }
  /// The newest pose with a unit quaternion; the default pose before the first.
  [[nodiscard]] DevicePose pose() const;
  [[nodiscard]] const ReceiverCounters& counters() const { return counters_; }
  [[nodiscard]] const ReceiverConfig& config() const { return config_; }

 private:
  ReceiverConfig config_;
  ReceiverCounters counters_;
  bool has_pose_ = false;
  PosePacket newest_;
  Nanos newest_arrival_ = 0;
};

}  // namespace tactus::haptics
