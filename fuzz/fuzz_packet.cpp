// libFuzzer target for the network bridge protocol. The input is a stream of datagrams,
// each as [length][control][length bytes]: the low 7 bits of control advance the arrival
// clock in milliseconds, the high bit re-stamps the datagram's trailing CRC-32 so that
// mutations of sequence, timestamp and numbers reach the checks behind the checksum.
// Every datagram goes to decode_force and to a PoseReceiver. Invariants: whatever decodes
// re-encodes to the same bytes; the receiver's pose is always finite with a unit
// quaternion; its counters account for every datagram.
#include <zlib.h>  // linked through Tactus::haptics

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "haptics/devices/network_protocol.hpp"

namespace {

using namespace tactus::haptics;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

template <class Decoded>
void check_round_trip(const Decoded& decoded, std::span<const std::byte> bytes) {
  if (!decoded.ok()) return;
  const auto again = encode(decoded.packet());
  check(again.size() == bytes.size() && std::equal(again.begin(), again.end(), bytes.begin()));
}

void restamp_crc(std::span<std::byte> bytes) {
  if (bytes.size() < 4) return;
  const std::size_t body = bytes.size() - 4;
  const auto crc = static_cast<std::uint32_t>(
      ::crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(body)));
  for (std::size_t i = 0; i < 4; ++i) bytes[body + i] = static_cast<std::byte>(crc >> (8 * i));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr tactus::Nanos kMs = 1'000'000;
  PoseReceiver receiver(ReceiverConfig{.device_index = 0, .timeout = 50 * kMs, .stale_after = 25 * kMs});
  std::array<std::byte, 256> datagram{};
  tactus::Nanos arrival = 0;
  std::size_t pos = 0;
  while (pos + 2 <= size) {
    const std::size_t length = std::min<std::size_t>(data[pos], size - pos - 2);
    const std::uint8_t control = data[pos + 1];
    pos += 2;
    std::memcpy(datagram.data(), data + pos, length);
    pos += length;
    arrival += (control & 0x7F) * kMs;
    const std::span<std::byte> bytes(datagram.data(), length);
    if (control & 0x80) restamp_crc(bytes);

    check_round_trip(decode_pose(bytes), bytes);
    check_round_trip(decode_force(bytes), bytes);
    receiver.on_datagram(bytes, arrival);

    const tactus::haptics::DevicePose pose = receiver.pose();
    check(pose.position.allFinite() && pose.orientation.coeffs().allFinite());
    check(std::abs(pose.orientation.norm() - 1.0) < 1e-9);
    check(receiver.has_pose() == (receiver.counters().accepted > 0));
    const ReceiverCounters& c = receiver.counters();
    check(c.datagrams ==
          c.accepted + c.malformed_total() + c.wrong_device + c.out_of_order + c.stale);
  }
  return 0;
}
