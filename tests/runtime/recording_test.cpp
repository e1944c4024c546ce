#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <bit>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "runtime/recording_csv.hpp"
#include "runtime/recording_reader.hpp"
#include "runtime/recording_writer.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::byte>;
using limits = std::numeric_limits<double>;

/// A fresh scratch directory per test, removed afterwards.
class RecordingFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("tactus_recording_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  [[nodiscard]] fs::path file(const std::string& name) const { return dir_ / name; }

 private:
  fs::path dir_;
};

Bytes read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Bytes out(s.size());
  std::memcpy(out.data(), s.data(), s.size());
  return out;
}

Recording read_prefix(const Bytes& bytes, std::size_t n) {
  return read_recording(std::span<const std::byte>(bytes.data(), n), "test.tacrec");
}

RecordingHeader make_header() {
  RecordingHeader h;
  h.scene_name = "needle block";
  h.scene_source = "scenes/needle_block.toml";
  h.scene_text = "[scene]\nname = \"needle block\"\n";
  h.mode = "lockstep";
  h.haptic_rate = 1000;
  h.simulation_rate = 250;
  h.devices = {"left", "right"};
  h.start_unix_ns = 1'700'000'000'123'456'789;
  h.tactus_version = "0.1.0";
  return h;
}

// Doubles that stress an encoding: extremes, subnormals, signed zero, infinities.
const double extremes[] = {
    limits::max(), limits::lowest(),   limits::min(),       limits::denorm_min(), -limits::denorm_min(),
    -0.0,          limits::infinity(), -limits::infinity(), limits::epsilon(),    1.0 / 3.0,
    -2.5e-300,     6.02214076e23};
constexpr std::size_t extreme_count = sizeof extremes / sizeof extremes[0];
double extreme(std::size_t i) { return extremes[i % extreme_count]; }

HapticFrame make_frame(std::uint64_t i) {
  HapticFrame f;
  f.frame = i * 0x9e3779b97f4a7c15ULL;
  f.t = 0.001 * static_cast<double>(i);
  f.device = static_cast<std::uint16_t>(i % 2);
  f.contact = static_cast<std::uint8_t>(i % 2);
  f.flags = static_cast<std::uint8_t>(i * 7);
  f.buttons = static_cast<std::uint32_t>(0xdeadbeefU ^ i);
  f.position = Vec3(extreme(i), extreme(i + 1), extreme(i + 2));
  f.orientation = Quat(extreme(i + 3), extreme(i + 4), extreme(i + 5), extreme(i + 6));
  f.force = Vec3(extreme(i + 7), extreme(i + 8), extreme(i + 9));
  f.torque = Vec3(extreme(i + 10), extreme(i + 11), 0.5 * static_cast<double>(i));
  f.proxy = Vec3(-1e-9 * static_cast<double>(i), extreme(i + 5), extreme(i + 9));
  f.compute_ns = static_cast<std::uint32_t>(4'000'000'000U - i);
  f.late_ns =
      static_cast<std::int32_t>(i % 3 == 0 ? std::numeric_limits<std::int32_t>::min() : -static_cast<std::int32_t>(i));
  return f;
}

SimulationStep make_step(std::uint64_t i) {
  return {.step = ~i,
          .t = extreme(i),
          .compute_ns = static_cast<std::uint32_t>(i * 1000 + 7),
          .solver_iterations = static_cast<std::uint32_t>(i),
          .late_ns = std::numeric_limits<std::int32_t>::max()};
}

Event make_event(std::uint64_t i, std::string text) {
  return {.t = extreme(i + 1),
          .kind = static_cast<EventKind>(i % event_kind_count),
          .device = static_cast<std::uint16_t>(i % 2),
          .value = extreme(i + 2),
          .text = std::move(text)};
}

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

void expect_same(const HapticFrame& a, const HapticFrame& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(bits(a.t), bits(b.t));
  EXPECT_EQ(a.device, b.device);
  EXPECT_EQ(a.contact, b.contact);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.buttons, b.buttons);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(a.position[k]), bits(b.position[k]));
    EXPECT_EQ(bits(a.force[k]), bits(b.force[k]));
    EXPECT_EQ(bits(a.torque[k]), bits(b.torque[k]));
    EXPECT_EQ(bits(a.proxy[k]), bits(b.proxy[k]));
  }
  for (int k = 0; k < 4; ++k) EXPECT_EQ(bits(a.orientation.coeffs()[k]), bits(b.orientation.coeffs()[k]));
  EXPECT_EQ(a.compute_ns, b.compute_ns);
  EXPECT_EQ(a.late_ns, b.late_ns);
}

void expect_same(const SimulationStep& a, const SimulationStep& b) {
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(bits(a.t), bits(b.t));
  EXPECT_EQ(a.compute_ns, b.compute_ns);
  EXPECT_EQ(a.solver_iterations, b.solver_iterations);
  EXPECT_EQ(a.late_ns, b.late_ns);
}

void expect_same(const Event& a, const Event& b) {
  EXPECT_EQ(bits(a.t), bits(b.t));
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.device, b.device);
  EXPECT_EQ(bits(a.value), bits(b.value));
  EXPECT_EQ(a.text, b.text);
}

void expect_same(const RecordingHeader& a, const RecordingHeader& b) {
  EXPECT_EQ(a.scene_name, b.scene_name);
  EXPECT_EQ(a.scene_source, b.scene_source);
  EXPECT_EQ(a.scene_text, b.scene_text);
  EXPECT_EQ(a.mode, b.mode);
  EXPECT_EQ(bits(a.haptic_rate), bits(b.haptic_rate));
  EXPECT_EQ(bits(a.simulation_rate), bits(b.simulation_rate));
  EXPECT_EQ(a.devices, b.devices);
  EXPECT_EQ(a.start_unix_ns, b.start_unix_ns);
  EXPECT_EQ(a.tactus_version, b.tactus_version);
}

/// Records read back must be the first n written, in order.
template <class T>
void expect_prefix(const std::vector<T>& read, const std::vector<T>& written, std::size_t n) {
  ASSERT_EQ(read.size(), n);
  for (std::size_t i = 0; i < n; ++i) expect_same(read[i], written[i]);
}

/// A small file whose every flush writes exactly one chunk, with the byte offset and
/// record counts after each chunk: the prefix a truncated file must give back.
struct Boundary {
  std::uint64_t bytes;
  std::size_t frames, steps, events;
};
struct SmallFile {
  Bytes bytes;
  std::vector<Boundary> boundaries;  ///< [0]: after the header chunk; last: after the end chunk
  std::vector<HapticFrame> frames;
  std::vector<SimulationStep> steps;
  std::vector<Event> events;
};

SmallFile write_small_file(const fs::path& path) {
  SmallFile s;
  RecordingWriter w(path, make_header());
  auto mark = [&] { s.boundaries.push_back({w.bytes_written(), s.frames.size(), s.steps.size(), s.events.size()}); };
  mark();
  auto frames = [&](int n) {
    for (int i = 0; i < n; ++i) {
      s.frames.push_back(make_frame(s.frames.size()));
      w.append(s.frames.back());
    }
    w.flush();
    mark();
  };
  auto steps = [&](int n) {
    for (int i = 0; i < n; ++i) {
      s.steps.push_back(make_step(s.steps.size()));
      w.append(s.steps.back());
    }
    w.flush();
    mark();
  };
  auto events = [&](std::vector<std::string> texts) {
    for (auto& text : texts) {
      s.events.push_back(make_event(s.events.size(), std::move(text)));
      w.append(s.events.back());
    }
    w.flush();
    mark();
  };
  frames(3);
  steps(2);
  events({"", "contact, \"begins\""});
  frames(2);
  events({std::string(300, 'x')});
  steps(3);
  frames(1);
  w.close();
  mark();
  s.bytes = read_bytes(path);
  return s;
}

std::uint32_t crc_of(const Bytes& b, std::size_t from, std::size_t to) {
  return static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(b.data() + from), static_cast<uInt>(to - from)));
}

void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) b[at + i] = static_cast<std::byte>((v >> (8 * i)) & 0xffU);
}

// ---------------------------------------------------------------------------------------

TEST_F(RecordingFiles, RoundTripsEveryRecordKindBitExactly) {
  RecordingHeader header = make_header();
  header.scene_text = std::string(200'000, 'a') + std::string("\0\xff\n\xc3\xa9", 5);
  header.devices = {"", "a device, with a comma", std::string(5000, 'd')};
  header.haptic_rate = limits::max();
  header.simulation_rate = limits::denorm_min();
  header.start_unix_ns = std::numeric_limits<std::int64_t>::min();

  std::vector<HapticFrame> frames;
  std::vector<SimulationStep> steps;
  std::vector<Event> events;
  const fs::path path = file("all.tacrec");
  {
    RecordingWriter w(path, header);
    // Enough records of each kind to fill several chunks and leave one partly filled.
    for (std::uint64_t i = 0; i < 3 * RecordingWriter::frames_per_chunk + 17; ++i) {
      frames.push_back(make_frame(i));
      frames.back().device = static_cast<std::uint16_t>(i % 3);
      w.append(frames.back());
      if (i % 3 == 0) {
        steps.push_back(make_step(i));
        w.append(steps.back());
      }
      if (i % 5 == 0) {
        events.push_back(make_event(i, i % 10 == 0 ? std::string() : std::string(i * 13 % 3000, 'e')));
        w.append(events.back());
      }
    }
    events.push_back(make_event(1, std::string(100'000, 'L')));  // longer than one chunk's budget
    w.append(events.back());
    w.close();
    EXPECT_FALSE(w.is_open());
    EXPECT_EQ(w.bytes_written(), fs::file_size(path));
  }
  const Recording rec = read_recording(path);
  EXPECT_TRUE(rec.complete);
  EXPECT_EQ(rec.truncation, "");
  EXPECT_GT(rec.good_chunks, 6U);
  expect_same(rec.header, header);
  expect_prefix(rec.frames, frames, frames.size());
  expect_prefix(rec.steps, steps, steps.size());
  expect_prefix(rec.events, events, events.size());
}

TEST_F(RecordingFiles, EmptyRecordingHasHeaderAndEndChunkOnly) {
  const fs::path path = file("empty.tacrec");
  { RecordingWriter w(path, RecordingHeader{}); }  // the destructor closes it
  const Recording rec = read_recording(path);
  EXPECT_TRUE(rec.complete);
  EXPECT_EQ(rec.good_chunks, 2U);
  EXPECT_TRUE(rec.frames.empty() && rec.steps.empty() && rec.events.empty());
  expect_same(rec.header, RecordingHeader{});
}

TEST_F(RecordingFiles, TruncationAtEveryByteGivesTheRecordsOfTheWholeChunksBeforeIt) {
  const SmallFile s = write_small_file(file("small.tacrec"));
  ASSERT_EQ(s.boundaries.back().bytes, s.bytes.size());
  ASSERT_EQ(s.boundaries.size(), 9U);  // header, seven data chunks, end
  const std::uint64_t header_end = s.boundaries.front().bytes;
  for (std::size_t n = 0; n <= s.bytes.size(); ++n) {
    SCOPED_TRACE("file cut to " + std::to_string(n) + " bytes");
    if (n < header_end) {
      try {
        (void)read_prefix(s.bytes, n);
        ADD_FAILURE() << "a file without a whole header chunk was accepted";
      } catch (const InputError& e) {
        EXPECT_TRUE(e.where().byte_offset.has_value());
        EXPECT_LE(*e.where().byte_offset, n);
      }
      continue;
    }
    Recording rec;
    ASSERT_NO_THROW(rec = read_prefix(s.bytes, n));
    std::size_t k = 0;  // the last chunk wholly inside the prefix
    while (k + 1 < s.boundaries.size() && s.boundaries[k + 1].bytes <= n) ++k;
    const Boundary& b = s.boundaries[k];
    expect_prefix(rec.frames, s.frames, b.frames);
    expect_prefix(rec.steps, s.steps, b.steps);
    expect_prefix(rec.events, s.events, b.events);
    EXPECT_EQ(rec.good_chunks, k + 1);
    EXPECT_EQ(rec.complete, n == s.bytes.size());
    if (!rec.complete) {
      const std::string where = "chunk " + std::to_string(k + 1) + " at byte " + std::to_string(b.bytes) + ": ";
      EXPECT_EQ(rec.truncation.substr(0, where.size()), where) << rec.truncation;
      EXPECT_NE(rec.truncation.find(n == b.bytes ? "without an end chunk" : "cut short"), std::string::npos)
          << rec.truncation;
    } else {
      EXPECT_EQ(rec.truncation, "");
    }
  }
}

TEST_F(RecordingFiles, CorruptByteDropsItsChunkAndEveryLaterOne) {
  const SmallFile s = write_small_file(file("small.tacrec"));
  for (std::size_t p = s.boundaries.front().bytes; p < s.bytes.size(); ++p) {
    SCOPED_TRACE("byte " + std::to_string(p) + " corrupted");
    Bytes bad = s.bytes;
    bad[p] ^= std::byte{0x5a};
    Recording rec;
    ASSERT_NO_THROW(rec = read_prefix(bad, bad.size()));
    std::size_t k = 0;  // the corrupted chunk starts at boundaries[k]
    while (s.boundaries[k + 1].bytes <= p) ++k;
    const Boundary& b = s.boundaries[k];
    expect_prefix(rec.frames, s.frames, b.frames);
    expect_prefix(rec.steps, s.steps, b.steps);
    expect_prefix(rec.events, s.events, b.events);
    EXPECT_FALSE(rec.complete);
    const std::string where = "chunk " + std::to_string(k + 1) + " at byte " + std::to_string(b.bytes) + ": ";
    EXPECT_EQ(rec.truncation.substr(0, where.size()), where) << rec.truncation;
    const std::size_t in_chunk = p - b.bytes;
    if (in_chunk < 4) {
      EXPECT_NE(rec.truncation.find("bad chunk magic"), std::string::npos) << rec.truncation;
    } else if (in_chunk < 12 || in_chunk >= 16) {  // kind, count, payload or the checksum itself
      EXPECT_NE(rec.truncation.find("checksum mismatch"), std::string::npos) << rec.truncation;
    }
  }
}

TEST_F(RecordingFiles, BadMagicVersionOrHeaderChunkIsAnInputErrorWithItsOffset) {
  const SmallFile s = write_small_file(file("small.tacrec"));
  auto error_of = [](const Bytes& b) -> InputError {
    try {
      (void)read_prefix(b, b.size());
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError";
    return InputError("none");
  };
  Bytes bad = s.bytes;
  bad[3] = std::byte{'x'};
  InputError e = error_of(bad);
  EXPECT_EQ(e.where().byte_offset, 0U);
  EXPECT_NE(e.reason().find("bad file magic"), std::string::npos) << e.what();

  for (const std::uint32_t version : {0U, 2U, 0xffffffffU}) {
    bad = s.bytes;
    put_u32(bad, 8, version);
    e = error_of(bad);
    EXPECT_EQ(e.where().byte_offset, 8U);
    EXPECT_NE(e.reason().find("unsupported recording format version " + std::to_string(version)), std::string::npos)
        << e.what();
  }

  bad = s.bytes;
  bad[40] ^= std::byte{1};  // inside the header chunk's payload
  e = error_of(bad);
  EXPECT_EQ(e.where().byte_offset, 12U);
  EXPECT_NE(e.reason().find("header chunk: checksum mismatch"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("test.tacrec"), std::string::npos) << e.what();

  e = error_of(Bytes{});
  EXPECT_NE(e.reason().find("truncated file"), std::string::npos) << e.what();
  const std::string text = "[scene]\nname = \"not a recording\"\n";
  Bytes toml(text.size());
  std::memcpy(toml.data(), text.data(), text.size());
  EXPECT_NE(error_of(toml).reason().find("bad file magic"), std::string::npos);

  EXPECT_THROW((void)read_recording(file("missing.tacrec")), InputError);
}

TEST_F(RecordingFiles, ChunkWithValidChecksumButBadContentStopsReading) {
  const SmallFile s = write_small_file(file("small.tacrec"));
  // Rewrites a field of chunk k and fixes its checksum, as a buggy writer would.
  auto patched = [&](std::size_t k, std::size_t payload_offset, std::uint32_t value, std::size_t width) {
    Bytes b = s.bytes;
    const std::size_t start = s.boundaries[k].bytes, end = s.boundaries[k + 1].bytes;
    for (std::size_t i = 0; i < width; ++i)
      b[start + 16 + payload_offset + i] = static_cast<std::byte>((value >> (8 * i)) & 0xffU);
    put_u32(b, end - 4, crc_of(b, start + 4, end - 4));
    return read_prefix(b, b.size());
  };
  // Chunk 0 after the header: 3 frames; its first frame's device is at payload byte 16.
  Recording rec = patched(0, 16, 7, 2);
  EXPECT_TRUE(rec.frames.empty());
  EXPECT_NE(rec.truncation.find("frame 0 is for device 7 but the header lists 2 devices"), std::string::npos)
      << rec.truncation;
  // Chunk 2 after the header: 2 events; the first kind is at payload byte 8.
  rec = patched(2, 8, 999, 2);
  expect_prefix(rec.frames, s.frames, 3);
  expect_prefix(rec.steps, s.steps, 2);
  EXPECT_TRUE(rec.events.empty());
  EXPECT_NE(rec.truncation.find("event 0 has unknown kind 999"), std::string::npos) << rec.truncation;
  // The second event's text length (payload byte 24 + 20) made larger than the chunk.
  rec = patched(2, 44, 1'000'000, 4);
  EXPECT_TRUE(rec.events.empty());
  EXPECT_NE(rec.truncation.find("event 1 text length 1000000 exceeds"), std::string::npos) << rec.truncation;
  // A count that promises more frames than the payload holds.
  Bytes b = s.bytes;
  const std::size_t start = s.boundaries[0].bytes, end = s.boundaries[1].bytes;
  put_u32(b, start + 8, 0xffffffffU);
  put_u32(b, end - 4, crc_of(b, start + 4, end - 4));
  rec = read_prefix(b, b.size());
  EXPECT_TRUE(rec.frames.empty());
  EXPECT_NE(rec.truncation.find("declares 4294967295 records"), std::string::npos) << rec.truncation;
}

TEST_F(RecordingFiles, KilledWriterLeavesEveryFlushedRecordReadable) {
  const fs::path path = file("killed.tacrec");
  constexpr int rounds = 3, frames_per_round = 10, steps_per_round = 5, events_per_round = 2;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      RecordingWriter w(path, make_header());
      for (int r = 0; r < rounds; ++r) {
        for (int i = 0; i < frames_per_round; ++i)
          w.append(make_frame(static_cast<std::uint64_t>(r * frames_per_round + i)));
        for (int i = 0; i < steps_per_round; ++i)
          w.append(make_step(static_cast<std::uint64_t>(r * steps_per_round + i)));
        for (int i = 0; i < events_per_round; ++i)
          w.append(make_event(static_cast<std::uint64_t>(r * events_per_round + i), "round " + std::to_string(r)));
        w.flush();
      }
      for (int i = 0; i < 7; ++i) w.append(make_frame(1000 + static_cast<std::uint64_t>(i)));  // never flushed
      ::raise(SIGKILL);
    } catch (...) {
    }
    ::_exit(3);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "child exited with " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGKILL);

  const Recording rec = read_recording(path);
  EXPECT_FALSE(rec.complete);
  EXPECT_NE(rec.truncation.find("without an end chunk"), std::string::npos) << rec.truncation;
  expect_same(rec.header, make_header());
  ASSERT_EQ(rec.frames.size(), std::size_t{rounds * frames_per_round});
  ASSERT_EQ(rec.steps.size(), std::size_t{rounds * steps_per_round});
  ASSERT_EQ(rec.events.size(), std::size_t{rounds * events_per_round});
  for (std::size_t i = 0; i < rec.frames.size(); ++i) expect_same(rec.frames[i], make_frame(i));
  for (std::size_t i = 0; i < rec.steps.size(); ++i) expect_same(rec.steps[i], make_step(i));
  for (std::size_t i = 0; i < rec.events.size(); ++i)
    expect_same(rec.events[i], make_event(i, "round " + std::to_string(i / events_per_round)));
}

TEST_F(RecordingFiles, ChunksGoOutWhenFullAndOnFlush) {
  RecordingWriter w(file("chunks.tacrec"), make_header());
  const std::uint64_t after_header = w.bytes_written();
  EXPECT_EQ(after_header, fs::file_size(w.path()));
  for (std::uint32_t i = 0; i + 1 < RecordingWriter::frames_per_chunk; ++i) w.append(make_frame(i));
  EXPECT_EQ(w.bytes_written(), after_header);
  w.append(make_frame(9));
  const std::uint64_t one_chunk = 16 + 160 * std::uint64_t{RecordingWriter::frames_per_chunk} + 4;
  EXPECT_EQ(w.bytes_written(), after_header + one_chunk);
  EXPECT_EQ(fs::file_size(w.path()), w.bytes_written());
  w.append(make_step(1));
  EXPECT_EQ(w.bytes_written(), after_header + one_chunk);
  w.flush();
  EXPECT_EQ(w.bytes_written(), after_header + one_chunk + 16 + 28 + 4);
  w.close();
  EXPECT_THROW(w.append(make_step(2)), std::logic_error);
}

TEST_F(RecordingFiles, MovedWriterKeepsWriting) {
  const fs::path path = file("moved.tacrec");
  RecordingWriter a(path, make_header());
  a.append(make_frame(0));
  RecordingWriter b(std::move(a));
  b.append(make_frame(1));
  RecordingWriter c(file("other.tacrec"), make_header());
  c = std::move(b);  // closes other.tacrec cleanly first
  c.close();
  EXPECT_TRUE(read_recording(file("other.tacrec")).complete);
  const Recording rec = read_recording(path);
  EXPECT_TRUE(rec.complete);
  ASSERT_EQ(rec.frames.size(), 2U);
  expect_same(rec.frames[1], make_frame(1));
}

TEST_F(RecordingFiles, WriterErrorsNameTheFileAndTheReason) {
  try {
    RecordingWriter w(file("no/such/dir/x.tacrec"), make_header());
    ADD_FAILURE() << "created a file in a missing directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/dir/x.tacrec"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
  if (fs::exists("/dev/full")) {  // every write fails with ENOSPC
    try {
      RecordingWriter w("/dev/full", make_header());
      ADD_FAILURE() << "writing to /dev/full succeeded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
    }
  }
  RecordingWriter w(file("devices.tacrec"), make_header());
  HapticFrame f = make_frame(0);
  f.device = 2;  // the header lists two devices
  EXPECT_THROW(w.append(f), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------

/// One CSV line split into fields, RFC 4180 quotes undone.
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::vector<std::string> csv_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

template <class T>
T parse(const std::string& field) {
  T v{};
  const auto r = std::from_chars(field.data(), field.data() + field.size(), v);
  EXPECT_TRUE(r.ec == std::errc() && r.ptr == field.data() + field.size()) << "'" << field << "'";
  return v;
}

TEST(RecordingCsv, FrameRowsReadBackToTheSameValues) {
  Recording rec;
  rec.header.devices = {"left", "right, \"main\""};
  HapticFrame f = make_frame(5);
  f.device = 1;
  f.compute_ns = 1234;
  f.late_ns = -500;
  rec.frames = {make_frame(0), f};
  std::ostringstream out;
  write_frames_csv(rec, out);
  const auto lines = csv_lines(out.str());
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(lines[0],
            "t,device,frame,x,y,z,qw,qx,qy,qz,buttons,fx,fy,fz,tx,ty,tz,contact,flags,"
            "proxy_x,proxy_y,proxy_z,compute_us,late_us");
  const auto v = split_csv(lines[2]);
  ASSERT_EQ(v.size(), 24U);
  EXPECT_EQ(bits(parse<double>(v[0])), bits(f.t));
  EXPECT_EQ(v[1], "right, \"main\"");
  EXPECT_EQ(parse<std::uint64_t>(v[2]), f.frame);
  const double coords[] = {f.position.x(),    f.position.y(),    f.position.z(),   f.orientation.w(),
                           f.orientation.x(), f.orientation.y(), f.orientation.z()};
  for (int k = 0; k < 7; ++k) EXPECT_EQ(bits(parse<double>(v[3 + k])), bits(coords[k])) << "column " << 3 + k;
  EXPECT_EQ(parse<std::uint32_t>(v[10]), f.buttons);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(parse<double>(v[11 + k])), bits(f.force[k]));
    EXPECT_EQ(bits(parse<double>(v[14 + k])), bits(f.torque[k]));
    EXPECT_EQ(bits(parse<double>(v[19 + k])), bits(f.proxy[k]));
  }
  EXPECT_EQ(parse<unsigned>(v[17]), f.contact);
  EXPECT_EQ(parse<unsigned>(v[18]), f.flags);
  EXPECT_EQ(parse<double>(v[22]), 1.234);
  EXPECT_EQ(parse<double>(v[23]), -0.5);
  EXPECT_EQ(split_csv(lines[1])[1], "left");
}

TEST(RecordingCsv, StepAndEventRows) {
  Recording rec;
  rec.header.devices = {"pen"};
  rec.steps = {{.step = 42, .t = 0.1, .compute_ns = 2500, .solver_iterations = 17, .late_ns = 1000}};
  rec.events = {
      {.t = 1.5, .kind = EventKind::force_clamped, .device = 0, .value = 12.5, .text = "he said \"stop\", twice"},
      {.t = 2, .kind = EventKind::simulation_overrun, .device = 3, .value = 0, .text = "plain"}};
  std::ostringstream steps;
  write_steps_csv(rec, steps);
  EXPECT_EQ(steps.str(), "t,step,compute_us,solver_iterations,late_us\n0.1,42,2.5,17,1\n");
  std::ostringstream events;
  write_events_csv(rec, events);
  const auto lines = csv_lines(events.str());
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(lines[0], "t,kind,device,value,text");
  EXPECT_EQ(lines[1], "1.5,force_clamped,pen,12.5,\"he said \"\"stop\"\", twice\"");
  EXPECT_EQ(split_csv(lines[1])[4], rec.events[0].text);
  EXPECT_EQ(lines[2], "2,simulation_overrun,3,0,plain");  // no device 3: its index
}

}  // namespace
}  // namespace tactus::runtime
