#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "haptics/devices/network_device.hpp"
#include "haptics/devices/network_protocol.hpp"

namespace tactus::haptics {
namespace {

constexpr Nanos kMs = 1'000'000;

PosePacket sample_pose(std::uint32_t sequence = 7, std::uint64_t timestamp_ns = 1'000'000) {
  PosePacket p;
  p.device_index = 0;
  p.sequence = sequence;
  p.timestamp_ns = timestamp_ns;
  p.position = Vec3(0.01, -0.02, 0.03);
  p.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  p.buttons = 0b101;
  return p;
}

std::vector<std::byte> bytes_of(const std::string& hex) {
  std::vector<std::byte> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
    out.push_back(static_cast<std::byte>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return out;
}

template <std::size_t N>
std::span<const std::byte> view(const std::array<std::byte, N>& a) {
  return std::span<const std::byte>(a);
}

// ---- encoding and decoding -----------------------------------------------------------

TEST(NetworkProtocol, PoseRoundTrip) {
  const PosePacket in = sample_pose(0xFFFFFFF0u, 0x0123456789ABCDEFull);
  const auto bytes = encode(in);
  const auto out = decode_pose(view(bytes));
  ASSERT_TRUE(out.ok()) << to_string(out.error());
  EXPECT_EQ(out.packet().device_index, in.device_index);
  EXPECT_EQ(out.packet().sequence, in.sequence);
  EXPECT_EQ(out.packet().timestamp_ns, in.timestamp_ns);
  EXPECT_EQ(out.packet().position, in.position);  // bit for bit
  EXPECT_EQ(out.packet().orientation.coeffs(), in.orientation.coeffs());
  EXPECT_EQ(out.packet().buttons, in.buttons);
}

TEST(NetworkProtocol, ForceRoundTrip) {
  ForcePacket in;
  in.device_index = 9;
  in.sequence = 12345;
  in.pose_sequence = 0xFFFFFFFFu;
  in.timestamp_ns = 987654321;
  in.force = Vec3(1.5, -2.25, 1e-9);
  in.torque = Vec3(0.0, -0.0, 3.0);
  in.flags = kForceClamped | kForceLinkTimeout;
  const auto out = decode_force(view(encode(in)));
  ASSERT_TRUE(out.ok()) << to_string(out.error());
  EXPECT_EQ(out.packet().device_index, in.device_index);
  EXPECT_EQ(out.packet().sequence, in.sequence);
  EXPECT_EQ(out.packet().pose_sequence, in.pose_sequence);
  EXPECT_EQ(out.packet().timestamp_ns, in.timestamp_ns);
  EXPECT_EQ(out.packet().force, in.force);
  EXPECT_EQ(out.packet().torque, in.torque);
  EXPECT_EQ(out.packet().flags, in.flags);
}

// Reference bytes from Python's struct ('<4sHHIQ3d4dI', '<4sHHIIQ3d3dI') and zlib.crc32,
// an implementation independent of this one (examples/network_driver.py uses the same).
TEST(NetworkProtocol, PoseMatchesIndependentEncoding) {
  PosePacket p;
  p.device_index = 3;
  p.sequence = 0xDEADBEEF;
  p.timestamp_ns = 123456789012345;
  p.position = Vec3(0.1, -0.25, 1.5);
  p.orientation = Quat(0.5, 0.5, -0.5, 0.5);
  p.buttons = 5;
  const auto expected = bytes_of(
      "54504f5301000300efbeadde79df0d86487000009a9999999999b93f000000000000d0bf000000000000f83f"
      "000000000000e03f000000000000e03f000000000000e0bf000000000000e03f05000000632f5d5b");
  const auto actual = encode(p);
  ASSERT_EQ(expected.size(), actual.size());
  EXPECT_TRUE(std::equal(actual.begin(), actual.end(), expected.begin()));
  EXPECT_TRUE(decode_pose(expected).ok());
}

TEST(NetworkProtocol, ForceMatchesIndependentEncoding) {
  ForcePacket f;
  f.device_index = 2;
  f.sequence = 7;
  f.pose_sequence = 0xFFFFFFFF;
  f.timestamp_ns = 42;
  f.force = Vec3(1.0, -2.0, 0.5);
  f.torque = Vec3(0.0, 0.125, -3.0);
  f.flags = 3;
  const auto expected = bytes_of(
      "544652430100020007000000ffffffff2a00000000000000000000000000f03f00000000000000c000000000"
      "0000e03f0000000000000000000000000000c03f00000000000008c003000000c2be9480");
  const auto actual = encode(f);
  ASSERT_EQ(expected.size(), actual.size());
  EXPECT_TRUE(std::equal(actual.begin(), actual.end(), expected.begin()));
}

TEST(NetworkProtocol, EveryTruncationAndExtensionIsWrongSize) {
  const auto pose = encode(sample_pose());
  for (std::size_t n = 0; n < pose.size(); ++n) {
    const auto r = decode_pose(view(pose).first(n));
    ASSERT_FALSE(r.ok()) << n;
    EXPECT_EQ(r.error(), PacketError::wrong_size) << n;
  }
  std::vector<std::byte> longer(pose.begin(), pose.end());
  longer.push_back(std::byte{0});
  EXPECT_EQ(decode_pose(longer).error(), PacketError::wrong_size);

  const auto force = encode(ForcePacket{});
  for (std::size_t n = 0; n < force.size(); ++n)
    EXPECT_EQ(decode_force(view(force).first(n)).error(), PacketError::wrong_size) << n;
}

TEST(NetworkProtocol, EveryFlippedBitIsRejected) {
  const auto good = encode(sample_pose());
  for (std::size_t bit = 0; bit < 8 * good.size(); ++bit) {
    auto bad = good;
    bad[bit / 8] ^= static_cast<std::byte>(1u << (bit % 8));
    const auto r = decode_pose(view(bad));
    ASSERT_FALSE(r.ok()) << "bit " << bit;
    const PacketError expected = bit < 32   ? PacketError::bad_magic
                                 : bit < 48 ? PacketError::bad_version
                                            : PacketError::bad_checksum;
    EXPECT_EQ(r.error(), expected) << "bit " << bit;
  }
  const auto force = encode(ForcePacket{});
  for (std::size_t bit = 64; bit < 8 * force.size(); ++bit) {
    auto bad = force;
    bad[bit / 8] ^= static_cast<std::byte>(1u << (bit % 8));
    EXPECT_EQ(decode_force(view(bad)).error(), PacketError::bad_checksum) << "bit " << bit;
  }
}

TEST(NetworkProtocol, NonFiniteNumbersAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    PosePacket p = sample_pose();
    p.position[i] = nan;
    EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::non_finite);
    p.position[i] = -inf;
    EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::non_finite);
  }
  for (int i = 0; i < 4; ++i) {
    PosePacket p = sample_pose();
    p.orientation.coeffs()[i] = nan;
    EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::non_finite);
  }
  ForcePacket f;
  f.torque.y() = inf;
  EXPECT_EQ(decode_force(view(encode(f))).error(), PacketError::non_finite);
  f = ForcePacket{};
  f.force.x() = nan;
  EXPECT_EQ(decode_force(view(encode(f))).error(), PacketError::non_finite);
}

TEST(NetworkProtocol, QuaternionMustBeNearUnitNorm) {
  PosePacket p = sample_pose();
  p.orientation = Quat(2.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::bad_quaternion);
  p.orientation = Quat(0.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::bad_quaternion);
  // Rounding from a driver's single-precision maths is accepted, then normalized.
  p.orientation = Quat(1.005, 0.0, 0.0, 0.0);
  const auto ok = decode_pose(view(encode(p)));
  ASSERT_TRUE(ok.ok());
  PoseReceiver receiver;
  ASSERT_TRUE(receiver.on_datagram(view(encode(p)), 0));
  EXPECT_NEAR(receiver.pose().orientation.norm(), 1.0, 1e-15);
}

TEST(NetworkProtocol, AbsurdPositionIsOutOfRange) {
  PosePacket p = sample_pose();
  p.position.z() = -1e6;
  EXPECT_EQ(decode_pose(view(encode(p))).error(), PacketError::out_of_range);
}

TEST(NetworkProtocol, WrongMagicAndVersion) {
  EXPECT_EQ(decode_pose(view(encode(ForcePacket{}))).error(), PacketError::bad_magic);
  EXPECT_EQ(decode_force(view(encode(sample_pose()))).error(), PacketError::bad_magic);
  auto v2 = encode(sample_pose());
  v2[4] = std::byte{2};
  EXPECT_EQ(decode_pose(view(v2)).error(), PacketError::bad_version);
  // A future version may have another size: reported as the version, not the size.
  EXPECT_EQ(decode_pose(view(v2).first(40)).error(), PacketError::bad_version);
}

TEST(NetworkProtocol, ErrorsHaveDistinctNames) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < kPacketErrorCount; ++i)
    names.insert(to_string(static_cast<PacketError>(i)));
  EXPECT_EQ(names.size(), kPacketErrorCount);
  EXPECT_EQ(names.count("unknown"), 0u);
}

// ---- the receiver's rules --------------------------------------------------------------

struct NetworkReceiver : ::testing::Test {
  ReceiverConfig config{.device_index = 0, .timeout = 50 * kMs, .stale_after = 10 * kMs};
  PoseReceiver receiver{config};

  bool offer(std::uint32_t sequence, Nanos driver_time, Nanos arrival) {
    return receiver.on_datagram(
        view(encode(sample_pose(sequence, static_cast<std::uint64_t>(driver_time)))), arrival);
  }
  void expect_consistent_counts() const {
    const ReceiverCounters& c = receiver.counters();
    EXPECT_EQ(c.datagrams,
              c.accepted + c.malformed_total() + c.wrong_device + c.out_of_order + c.stale);
  }
};

TEST_F(NetworkReceiver, KeepsTheNewestPose) {
  EXPECT_FALSE(receiver.has_pose());
  EXPECT_EQ(receiver.pose().position, Vec3::Zero());
  EXPECT_TRUE(offer(1, 1 * kMs, 1 * kMs));
  EXPECT_TRUE(offer(2, 2 * kMs, 2 * kMs));
  EXPECT_TRUE(offer(5, 3 * kMs, 3 * kMs));  // gaps are fine: lost packets
  EXPECT_EQ(receiver.newest().sequence, 5u);
  EXPECT_EQ(receiver.pose().position, sample_pose().position);
  EXPECT_EQ(receiver.pose().buttons, sample_pose().buttons);
  EXPECT_EQ(receiver.counters().accepted, 3u);
  expect_consistent_counts();
}

TEST_F(NetworkReceiver, DuplicateAndOlderSequencesAreIgnored) {
  EXPECT_TRUE(offer(10, 1 * kMs, 1 * kMs));
  EXPECT_FALSE(offer(10, 2 * kMs, 2 * kMs));  // duplicate
  EXPECT_FALSE(offer(9, 3 * kMs, 3 * kMs));   // reordered
  EXPECT_TRUE(offer(11, 4 * kMs, 4 * kMs));
  EXPECT_FALSE(offer(10, 5 * kMs, 5 * kMs));
  EXPECT_EQ(receiver.newest().sequence, 11u);
  EXPECT_EQ(receiver.counters().out_of_order, 3u);
  expect_consistent_counts();
}

TEST_F(NetworkReceiver, SequenceWrapsAround) {
  Nanos t = 0;
  for (std::uint32_t s : {0xFFFFFFFEu, 0xFFFFFFFFu, 0u, 1u}) {
    t += kMs;
    EXPECT_TRUE(offer(s, t, t)) << s;
  }
  t += kMs;
  EXPECT_FALSE(offer(0xFFFFFFFFu, t, t));  // before 1 in serial order
  EXPECT_FALSE(offer(0x80000001u, t, t));  // more than half the range ahead: behind
  EXPECT_TRUE(offer(0x80000000u, t, t));   // just under half the range ahead of 1
  EXPECT_EQ(receiver.counters().out_of_order, 2u);
}

TEST_F(NetworkReceiver, TimestampGoingBackwardsIsStale) {
  EXPECT_TRUE(offer(1, 100 * kMs, 1 * kMs));
  EXPECT_FALSE(offer(2, 99 * kMs, 2 * kMs));
  EXPECT_TRUE(offer(3, 100 * kMs, 3 * kMs));  // an equal timestamp is a coarse clock
  EXPECT_EQ(receiver.counters().stale, 1u);
  EXPECT_EQ(receiver.newest().sequence, 3u);
}

TEST_F(NetworkReceiver, PoseDelayedBeyondStaleAfterIsStale) {
  // The driver clock is offset arbitrarily from ours: only advances are compared.
  const Nanos offset = 7'000'000'000;
  EXPECT_TRUE(offer(1, offset + 0, 0));
  EXPECT_TRUE(offer(2, offset + 1 * kMs, 1 * kMs));
  // Sent 1 ms after the previous one, arrives 15 ms later: 14 ms of extra delay > 10 ms.
  EXPECT_FALSE(offer(3, offset + 2 * kMs, 16 * kMs));
  // 9 ms of extra delay is within stale_after.
  EXPECT_TRUE(offer(4, offset + 8 * kMs, 16 * kMs));
  EXPECT_EQ(receiver.counters().stale, 1u);
  expect_consistent_counts();
}

TEST_F(NetworkReceiver, OtherDeviceIndexIsCounted) {
  PosePacket p = sample_pose(1);
  p.device_index = 1;
  EXPECT_FALSE(receiver.on_datagram(view(encode(p)), 0));
  EXPECT_FALSE(receiver.has_pose());
  EXPECT_EQ(receiver.counters().wrong_device, 1u);
}

TEST_F(NetworkReceiver, MalformedDatagramsAreCountedByReason) {
  auto corrupt = encode(sample_pose(1));
  corrupt[30] ^= std::byte{0x40};
  EXPECT_FALSE(receiver.on_datagram(view(corrupt), 0));
  EXPECT_FALSE(receiver.on_datagram(view(corrupt).first(10), 0));
  EXPECT_FALSE(receiver.on_datagram({}, 0));
  EXPECT_FALSE(receiver.on_datagram(view(encode(ForcePacket{})), 0));
  PosePacket nan_pose = sample_pose(2);
  nan_pose.position.x() = std::nan("");
  EXPECT_FALSE(receiver.on_datagram(view(encode(nan_pose)), 0));
  EXPECT_FALSE(receiver.has_pose());
  const ReceiverCounters& c = receiver.counters();
  EXPECT_EQ(c.malformed_by(PacketError::bad_checksum), 1u);
  EXPECT_EQ(c.malformed_by(PacketError::wrong_size), 2u);
  EXPECT_EQ(c.malformed_by(PacketError::bad_magic), 1u);
  EXPECT_EQ(c.malformed_by(PacketError::non_finite), 1u);
  EXPECT_EQ(c.malformed_total(), 5u);
  expect_consistent_counts();
}

TEST_F(NetworkReceiver, AliveUntilTheTimeoutAfterTheLastValidPose) {
  EXPECT_FALSE(receiver.alive(0));
  ASSERT_TRUE(offer(1, 0, 100 * kMs));
  EXPECT_TRUE(receiver.alive(100 * kMs));
  EXPECT_TRUE(receiver.alive(150 * kMs));
  EXPECT_FALSE(receiver.alive(150 * kMs + 1));
  // Garbage keeps nothing alive.
  EXPECT_FALSE(receiver.on_datagram(view(encode(ForcePacket{})), 149 * kMs));
  EXPECT_FALSE(receiver.alive(151 * kMs));
  ASSERT_TRUE(offer(2, 60 * kMs, 160 * kMs));
  EXPECT_TRUE(receiver.alive(160 * kMs));
}

TEST_F(NetworkReceiver, RestartedDriverIsAcceptedAfterSilence) {
  ASSERT_TRUE(offer(5000, 9000 * kMs, 1 * kMs));
  EXPECT_FALSE(offer(0, 0, 20 * kMs));  // while alive a restart looks like reordering
  EXPECT_TRUE(offer(0, 0, 52 * kMs));   // after the timeout it starts a new stream
  EXPECT_TRUE(offer(1, 1 * kMs, 53 * kMs));
  EXPECT_EQ(receiver.counters().resyncs, 1u);
  EXPECT_EQ(receiver.newest().sequence, 1u);
}

// ---- the device over loopback ------------------------------------------------------------

// A driver's end of the link: a UDP socket on an ephemeral loopback port.
class Client {
 public:
  Client() {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    EXPECT_GE(fd_, 0);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  }
  ~Client() { ::close(fd_); }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  void send(std::span<const std::byte> bytes, std::uint16_t port) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to.sin_port = htons(port);
    ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  }
  /// One datagram, or nothing within the wait.
  std::optional<std::vector<std::byte>> receive(int wait_ms = 2000) const {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, wait_ms) != 1) return std::nullopt;
    std::vector<std::byte> buffer(512);
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
    if (n < 0) return std::nullopt;
    buffer.resize(static_cast<std::size_t>(n));
    return buffer;
  }

 private:
  int fd_ = -1;
};

NetworkConfig ephemeral() {
  NetworkConfig c;
  c.port = 0;
  return c;
}

// Loopback delivery is asynchronous in principle: poll until the device has a pose.
bool read_until_accepted(NetworkDevice& device, double t, std::uint64_t accepted) {
  for (int i = 0; i < 2000; ++i) {
    device.read(t);
    if (device.receiver_counters().accepted >= accepted) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

TEST(NetworkDevice, LoopbackPosesInForcesOut) {
  NetworkDevice device(ephemeral(), DeviceLimits{});
  ASSERT_NE(device.bound_port(), 0);
  EXPECT_STREQ(device.kind(), "network");
  Client client;

  EXPECT_FALSE(device.alive());
  EXPECT_EQ(device.read(0.0).position, Vec3::Zero());
  device.write(Vec3(1, 0, 0), Vec3::Zero());  // no peer yet: nothing sent
  EXPECT_EQ(device.counters().sent, 0u);
  EXPECT_FALSE(client.receive(50).has_value());

  const PosePacket sent = sample_pose(41, 5'000'000);
  client.send(view(encode(sent)), device.bound_port());
  ASSERT_TRUE(read_until_accepted(device, 1.0, 1));
  const DevicePose pose = device.read(1.0);
  EXPECT_EQ(pose.position, sent.position);
  EXPECT_NEAR(pose.orientation.angularDistance(sent.orientation), 0.0, 1e-12);
  EXPECT_EQ(pose.buttons, sent.buttons);
  EXPECT_TRUE(device.alive());

  device.set_safety_flags(kForceClamped);
  device.write(Vec3(0.5, -1.0, 2.0), Vec3(0.0, 0.01, 0.0));
  const auto reply = client.receive();
  ASSERT_TRUE(reply.has_value());
  const auto force = decode_force(*reply);
  ASSERT_TRUE(force.ok()) << to_string(force.error());
  EXPECT_EQ(force.packet().force, Vec3(0.5, -1.0, 2.0));
  EXPECT_EQ(force.packet().torque, Vec3(0.0, 0.01, 0.0));
  EXPECT_EQ(force.packet().pose_sequence, 41u);
  EXPECT_EQ(force.packet().device_index, 0u);
  EXPECT_EQ(force.packet().timestamp_ns, 1'000'000'000u);
  EXPECT_EQ(force.packet().flags, std::uint32_t{kForceClamped});

  device.write(Vec3::Zero(), Vec3::Zero());
  const auto second = client.receive();
  ASSERT_TRUE(second.has_value());
  ASSERT_TRUE(decode_force(*second).ok());
  EXPECT_EQ(decode_force(*second).packet().sequence, force.packet().sequence + 1);
  EXPECT_EQ(device.counters().sent, 2u);
  EXPECT_EQ(device.counters().send_errors, 0u);
}

TEST(NetworkDevice, SilenceEndsLivenessAndFlagsTheForce) {
  NetworkDevice device(ephemeral(), DeviceLimits{});  // timeout 0.05 s
  Client client;
  client.send(view(encode(sample_pose(1))), device.bound_port());
  ASSERT_TRUE(read_until_accepted(device, 2.0, 1));
  EXPECT_TRUE(device.alive());
  device.read(2.04);
  EXPECT_TRUE(device.alive());
  const DevicePose held = device.read(2.06);
  EXPECT_FALSE(device.alive());
  EXPECT_EQ(held.position, sample_pose().position);  // the last pose is kept

  device.write(Vec3(std::nan(""), 0, 0), Vec3::Zero());
  const auto reply = client.receive();
  ASSERT_TRUE(reply.has_value());
  const auto force = decode_force(*reply);
  ASSERT_TRUE(force.ok());
  EXPECT_EQ(force.packet().flags, std::uint32_t{kForceLinkTimeout | kForceNonFinite});
  EXPECT_EQ(force.packet().force, Vec3::Zero());
}

TEST(NetworkDevice, OtherDeviceIndexGetsNoForce) {
  NetworkConfig config = ephemeral();
  config.device_index = 2;
  NetworkDevice device(config, DeviceLimits{});
  Client client;
  client.send(view(encode(sample_pose(1))), device.bound_port());  // index 0
  for (int i = 0; i < 2000 && device.receiver_counters().datagrams == 0; ++i) {
    device.read(0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(device.receiver_counters().wrong_device, 1u);
  device.write(Vec3(1, 1, 1), Vec3::Zero());
  EXPECT_EQ(device.counters().sent, 0u);
}

TEST(NetworkDevice, FloodIsDrainedInBoundedSlicesAndTheValidPoseWins) {
  NetworkDevice device(ephemeral(), DeviceLimits{});
  Client client;
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> size(1, 300);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < 10000; ++i) {
    std::vector<std::byte> garbage(static_cast<std::size_t>(size(rng)));
    for (auto& b : garbage) b = static_cast<std::byte>(byte(rng));
    garbage[0] = std::byte{'X'};  // never a magic, so every one is wrong_size or bad_magic
    client.send(garbage, device.bound_port());
  }
  std::uint32_t sequence = 1;
  client.send(view(encode(sample_pose(sequence))), device.bound_port());

  // The kernel drops what its buffer cannot hold, valid poses included, so the driver
  // keeps sending (as a 1 kHz driver does) until one gets through.
  double t = 0.0;
  bool got_pose = false;
  for (int frame = 0; frame < 5000 && !got_pose; ++frame) {
    const std::uint64_t before = device.receiver_counters().datagrams;
    const auto start = std::chrono::steady_clock::now();
    device.read(t);
    const auto elapsed = std::chrono::steady_clock::now() - start;
    const std::uint64_t drained = device.receiver_counters().datagrams - before;
    ASSERT_LE(drained, static_cast<std::uint64_t>(NetworkDevice::kMaxDatagramsPerRead));
    EXPECT_LT(elapsed, std::chrono::milliseconds(500));  // a sanity bound, not a benchmark
    got_pose = device.alive();
    if (!got_pose && drained < NetworkDevice::kMaxDatagramsPerRead) {
      client.send(view(encode(sample_pose(++sequence))), device.bound_port());
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    t += 0.001;
  }
  ASSERT_TRUE(got_pose);
  EXPECT_EQ(device.read(t).position, sample_pose().position);

  const ReceiverCounters& c = device.receiver_counters();
  EXPECT_GT(device.counters().reads_at_budget, 0u);  // the flood outlasted one read
  EXPECT_GT(c.malformed_total(), 64u);
  EXPECT_LE(c.malformed_total(), 10000u);
  EXPECT_EQ(c.malformed_total(),
            c.malformed_by(PacketError::wrong_size) + c.malformed_by(PacketError::bad_magic));
  EXPECT_GT(c.malformed_by(PacketError::wrong_size), 0u);
  EXPECT_GT(c.malformed_by(PacketError::bad_magic), 0u);
  EXPECT_GE(c.accepted, 1u);
  EXPECT_EQ(c.datagrams, c.malformed_total() + c.accepted + c.out_of_order + c.stale);
  EXPECT_EQ(device.counters().receive_errors, 0u);
}

TEST(NetworkDevice, NonLoopbackAddressNeedsAllowRemote) {
  NetworkConfig config = ephemeral();
  config.address = "0.0.0.0";
  try {
    NetworkDevice device(config, DeviceLimits{});
    FAIL() << "bound a wildcard address without allow_remote";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("allow_remote"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.0.0.0:0"), std::string::npos) << e.what();
  }
  config.allow_remote = true;
  EXPECT_NO_THROW(NetworkDevice(config, DeviceLimits{}));
  // Allowed, but not an address of this machine: the bind itself fails.
  config.address = "192.0.2.1";
  try {
    NetworkDevice device(config, DeviceLimits{});
    FAIL() << "bound an address this machine does not have";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot bind UDP 192.0.2.1:0"), std::string::npos)
        << e.what();
  }
}

TEST(NetworkDevice, PortInUseNamesAddressPortAndReason) {
  // A socket without SO_REUSEADDR holds the port exclusively.
  const int holder = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(holder, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(holder, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  socklen_t length = sizeof local;
  ASSERT_EQ(::getsockname(holder, reinterpret_cast<sockaddr*>(&local), &length), 0);
  NetworkConfig config;
  config.port = ntohs(local.sin_port);
  try {
    NetworkDevice device(config, DeviceLimits{});
    ADD_FAILURE() << "bound a port in use";
  } catch (const InputError& e) {
    const std::string expected = "cannot bind UDP 127.0.0.1:" + std::to_string(config.port) +
                                 ": " + std::strerror(EADDRINUSE);
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
  ::close(holder);
}

TEST(NetworkDevice, BadConfigurationIsAnInputError) {
  NetworkConfig config = ephemeral();
  config.address = "localhost";
  EXPECT_THROW(NetworkDevice(config, DeviceLimits{}), InputError);
  config = ephemeral();
  config.port = 70000;
  EXPECT_THROW(NetworkDevice(config, DeviceLimits{}), InputError);
  config = ephemeral();
  config.timeout = 0.0;
  EXPECT_THROW(NetworkDevice(config, DeviceLimits{}), InputError);
  config.timeout = std::nan("");
  EXPECT_THROW(NetworkDevice(config, DeviceLimits{}), InputError);
}

}  // namespace
}  // namespace tactus::haptics
