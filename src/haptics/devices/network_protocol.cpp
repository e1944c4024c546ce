#include "haptics/devices/network_protocol.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>

namespace tactus::haptics {
namespace {

constexpr std::array<char, 4> kPoseMagic{'T', 'P', 'O', 'S'};
constexpr std::array<char, 4> kForceMagic{'T', 'F', 'R', 'C'};
constexpr std::size_t kHeaderSize = 8;  // magic, version, device index: common to every version
constexpr std::size_t kCrcSize = 4;

std::uint32_t crc32_of(std::span<const std::byte> bytes) {
  // Packets are a few dozen bytes, far below zlib's uInt length limit.
  return static_cast<std::uint32_t>(::crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()),
                                            static_cast<uInt>(bytes.size())));
}

// Little-endian by shifts, so the layout is the same on any host and independent of padding.
class Writer {
 public:
  explicit Writer(std::span<std::byte> out) : out_(out) {}
  void magic(const std::array<char, 4>& m) {
    for (char c : m) out_[pos_++] = static_cast<std::byte>(c);
  }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void f64(double v) { put(std::bit_cast<std::uint64_t>(v), 8); }
  void crc() { u32(crc32_of(out_.first(pos_))); }
  [[nodiscard]] std::size_t size() const { return pos_; }

 private:
  void put(std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out_[pos_++] = static_cast<std::byte>((v >> (8 * i)) & 0xFFu);
  }
  std::span<std::byte> out_;
  std::size_t pos_ = 0;
};

// Callers check the size first; every read stays within it.
class Reader {
 public:
  explicit Reader(std::span<const std::byte> in) : in_(in) {}
  bool magic(const std::array<char, 4>& m) {
    bool same = true;
    for (char c : m) same = same && in_[pos_++] == static_cast<std::byte>(c);
    return same;
  }
  std::uint16_t u16() { return static_cast<std::uint16_t>(get(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(get(4)); }
  std::uint64_t u64() { return get(8); }
  double f64() { return std::bit_cast<double>(get(8)); }
  Vec3 vec3() {
    const double x = f64(), y = f64(), z = f64();
    return {x, y, z};
  }
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  std::uint64_t get(int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::to_integer<std::uint64_t>(in_[pos_++]) << (8 * i);
    return v;
  }
  std::span<const std::byte> in_;
  std::size_t pos_ = 0;
};

// Magic, version and size, in that order, so a packet of another version is reported as
// such rather than as the wrong size.
std::optional<PacketError> check_frame(std::span<const std::byte> bytes,
                                       const std::array<char, 4>& magic, std::size_t size) {
  if (bytes.size() < kHeaderSize) return PacketError::wrong_size;
  Reader r(bytes);
  if (!r.magic(magic)) return PacketError::bad_magic;
  if (r.u16() != kProtocolVersion) return PacketError::bad_version;
  if (bytes.size() != size) return PacketError::wrong_size;
  Reader tail(bytes.subspan(size - kCrcSize));
  if (tail.u32() != crc32_of(bytes.first(size - kCrcSize))) return PacketError::bad_checksum;
  return std::nullopt;
}

}  // namespace

const char* to_string(PacketError error) {
  switch (error) {
    case PacketError::wrong_size: return "wrong size";
    case PacketError::bad_magic: return "bad magic";
    case PacketError::bad_version: return "unsupported version";
    case PacketError::bad_checksum: return "bad checksum";
    case PacketError::non_finite: return "non-finite number";
    case PacketError::bad_quaternion: return "quaternion not of unit norm";
    case PacketError::out_of_range: return "position out of range";
  }
  return "unknown";
}

std::array<std::byte, kPosePacketSize> encode(const PosePacket& packet) {
  std::array<std::byte, kPosePacketSize> out{};
  Writer w(out);
  w.magic(kPoseMagic);
  w.u16(kProtocolVersion);
  w.u16(packet.device_index);
  w.u32(packet.sequence);
  w.u64(packet.timestamp_ns);
  for (int i = 0; i < 3; ++i) w.f64(packet.position[i]);
  w.f64(packet.orientation.w());
  w.f64(packet.orientation.x());
  w.f64(packet.orientation.y());
  w.f64(packet.orientation.z());
  w.u32(packet.buttons);
  w.crc();
  return out;
}

std::array<std::byte, kForcePacketSize> encode(const ForcePacket& packet) {
  std::array<std::byte, kForcePacketSize> out{};
  Writer w(out);
  w.magic(kForceMagic);
  w.u16(kProtocolVersion);
  w.u16(packet.device_index);
  w.u32(packet.sequence);
  w.u32(packet.pose_sequence);
  w.u64(packet.timestamp_ns);
  for (int i = 0; i < 3; ++i) w.f64(packet.force[i]);
  for (int i = 0; i < 3; ++i) w.f64(packet.torque[i]);
  w.u32(packet.flags);
  w.crc();
  return out;
}

DecodeResult<PosePacket> decode_pose(std::span<const std::byte> bytes) {
  if (const auto error = check_frame(bytes, kPoseMagic, kPosePacketSize)) return *error;
  Reader r(bytes.subspan(6));
  PosePacket p;
  p.device_index = r.u16();
  p.sequence = r.u32();
  p.timestamp_ns = r.u64();
  p.position = r.vec3();
  const double w = r.f64(), x = r.f64(), y = r.f64(), z = r.f64();
  p.orientation = Quat(w, x, y, z);
  p.buttons = r.u32();
  if (!p.position.allFinite() || !p.orientation.coeffs().allFinite())
    return PacketError::non_finite;
  if (std::abs(p.orientation.norm() - 1.0) > kQuaternionNormTolerance)
    return PacketError::bad_quaternion;
  if (p.position.cwiseAbs().maxCoeff() > kMaxPositionMagnitude) return PacketError::out_of_range;
  return p;
}

DecodeResult<ForcePacket> decode_force(std::span<const std::byte> bytes) {
  if (const auto error = check_frame(bytes, kForceMagic, kForcePacketSize)) return *error;
  Reader r(bytes.subspan(6));
  ForcePacket p;
  p.device_index = r.u16();
  p.sequence = r.u32();
  p.pose_sequence = r.u32();
  p.timestamp_ns = r.u64();
  p.force = r.vec3();
  p.torque = r.vec3();
  p.flags = r.u32();
  if (!p.force.allFinite() || !p.torque.allFinite()) return PacketError::non_finite;
  return p;
}

std::uint64_t ReceiverCounters::malformed_total() const {
  return std::accumulate(malformed.begin(), malformed.end(), std::uint64_t{0});
}

PoseReceiver::PoseReceiver(ReceiverConfig config) : config_(config) {}

bool PoseReceiver::alive(Nanos now) const {
  if (!has_pose_) return false;
  if (now <= newest_arrival_) return true;
  // Unsigned: the difference of two int64 values may not fit in one.
  return static_cast<std::uint64_t>(now) - static_cast<std::uint64_t>(newest_arrival_) <=
         static_cast<std::uint64_t>(std::max<Nanos>(config_.timeout, 0));
}

bool PoseReceiver::on_datagram(std::span<const std::byte> datagram, Nanos arrival) {
  ++counters_.datagrams;
  const DecodeResult<PosePacket> decoded = decode_pose(datagram);
  if (!decoded.ok()) {
    ++counters_.malformed[static_cast<std::size_t>(decoded.error())];
    return false;
  }
  const PosePacket& pose = decoded.packet();
  if (pose.device_index != config_.device_index) {
    ++counters_.wrong_device;
    return false;
  }
  if (alive(arrival)) {
    // Serial-number arithmetic (RFC 1982): "after" means less than half the range ahead.
    const auto ahead = static_cast<std::int32_t>(pose.sequence - newest_.sequence);
    if (ahead <= 0) {
      ++counters_.out_of_order;
      return false;
    }
    if (pose.timestamp_ns < newest_.timestamp_ns) {
      ++counters_.stale;
      return false;
    }
    // Extra delay over the newest pose: how much more our clock advanced than the
    // driver's. Comparing advances, not clocks, needs no clock synchronization.
    const std::uint64_t driver_advance = pose.timestamp_ns - newest_.timestamp_ns;
    const std::uint64_t arrival_advance =
        arrival > newest_arrival_
            ? static_cast<std::uint64_t>(arrival) - static_cast<std::uint64_t>(newest_arrival_)
            : 0;
    const auto stale_after = static_cast<std::uint64_t>(std::max<Nanos>(config_.stale_after, 0));
    if (arrival_advance > driver_advance && arrival_advance - driver_advance > stale_after) {
      ++counters_.stale;
      return false;
    }
  } else if (has_pose_) {
    ++counters_.resyncs;
  }
  newest_ = pose;
  newest_arrival_ = has_pose_ ? std::max(arrival, newest_arrival_) : arrival;
  has_pose_ = true;
  ++counters_.accepted;
  return true;
}

DevicePose PoseReceiver::pose() const {
  DevicePose out;
  if (!has_pose_) return out;
  out.position = newest_.position;
  out.orientation = newest_.orientation.normalized();
  out.buttons = newest_.buttons;
  return out;
}

}  // namespace tactus::haptics
