// TripleBuffer, SeqLock and SpscRing: single-threaded behaviour, two-thread stress with
// consistency checks (run under TSan too), and no allocation on the hot paths.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/counting_allocator.hpp"
#include "core/seqlock.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"

namespace tactus {
namespace {

#ifdef TACTUS_SANITIZED
constexpr std::uint64_t kStressItems = 50'000;
#else
constexpr std::uint64_t kStressItems = 1'000'000;
#endif

/// A snapshot whose fields all derive from `sequence`: a torn read breaks the relation.
struct Snapshot {
  std::uint64_t sequence = 0;
  std::array<std::uint64_t, 30> payload{};

  void fill(std::uint64_t s) {
    sequence = s;
    for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = s * 31 + i;
  }
  [[nodiscard]] bool consistent() const {
    for (std::size_t i = 0; i < payload.size(); ++i)
      if (payload[i] != sequence * 31 + i) return false;
    return true;
  }
};

// ---------------------------------------------------------------- TripleBuffer

TEST(TripleBuffer, ReaderSeesInitialValueUntilFirstPublish) {
  TripleBuffer<int> buffer(7);
  EXPECT_EQ(buffer.read(), 7);
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.read(), 7);
  EXPECT_EQ(buffer.write_buffer(), 7);
}

TEST(TripleBuffer, UpdateTakesTheNewestPublishedValueOnce) {
  TripleBuffer<int> buffer;
  buffer.write_buffer() = 1;
  buffer.publish();
  EXPECT_TRUE(buffer.update());
  EXPECT_EQ(buffer.read(), 1);
  EXPECT_FALSE(buffer.update());
  EXPECT_EQ(buffer.read(), 1);

  // Two publishes before the reader looks: it skips to the newest.
  buffer.write_buffer() = 2;
  buffer.publish();
  buffer.write_buffer() = 3;
  buffer.publish();
  EXPECT_TRUE(buffer.update());
  EXPECT_EQ(buffer.read(), 3);
  EXPECT_FALSE(buffer.update());
}

TEST(TripleBuffer, WriterNeverWritesTheSlotTheReaderHolds) {
  TripleBuffer<int> buffer(0);
  for (int i = 1; i <= 20; ++i) {
    EXPECT_NE(&buffer.write_buffer(), &buffer.read()) << i;
    buffer.write_buffer() = i;
    buffer.publish();
    EXPECT_NE(&buffer.write_buffer(), &buffer.read()) << i;
    if (i % 3 == 0) {
      EXPECT_TRUE(buffer.update());
      EXPECT_EQ(buffer.read(), i);
    }
  }
}

TEST(TripleBuffer, InitialValueSizesEverySlot) {
  TripleBuffer<std::vector<double>> buffer(std::vector<double>(1000, 0.5));
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(buffer.write_buffer().size(), 1000u);
    buffer.write_buffer()[0] = i;
    buffer.publish();
    ASSERT_TRUE(buffer.update());
    EXPECT_EQ(buffer.read().size(), 1000u);
    EXPECT_EQ(buffer.read()[0], i);
  }
}

/// A writer thread publishing snapshots 1..kStressItems as fast as it can, then `done`.
template <class Buffer>
std::thread publish_in_sequence(Buffer& buffer, std::atomic<bool>& done) {
  return std::thread([&buffer, &done] {
    for (std::uint64_t s = 1; s <= kStressItems; ++s) {
      buffer.write_buffer().fill(s);
      buffer.publish();
    }
    done.store(true, std::memory_order_release);
  });
}

TEST(TripleBuffer, ReaderNeverSeesATornOrOlderSnapshot) {
  TripleBuffer<Snapshot> buffer;
  std::atomic<bool> done{false};
  std::thread writer = publish_in_sequence(buffer, done);
  std::uint64_t last = 0, updates = 0, torn = 0, backwards = 0;
  auto check = [&] {
    if (!buffer.update()) return;
    ++updates;
    const Snapshot& s = buffer.read();
    if (!s.consistent()) ++torn;
    if (s.sequence <= last) ++backwards;
    last = s.sequence;
  };
  while (!done.load(std::memory_order_acquire)) check();
  writer.join();
  check();  // the final publish is now visible
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_GT(updates, 0u);
  EXPECT_EQ(last, kStressItems);
}

// ---------------------------------------------------------------- QuadBuffer

TEST(QuadBuffer, ReaderKeepsTheSnapshotBeforeItsNewestUntilTheNextUpdate) {
  QuadBuffer<int> buffer(0);
  int newest = 0;
  for (int i = 1; i <= 30; ++i) {
    buffer.write_buffer() = i;
    buffer.publish();
    // The writer's next slot is neither of the two the reader holds.
    EXPECT_NE(&buffer.write_buffer(), &buffer.read()) << i;
    EXPECT_NE(&buffer.write_buffer(), &buffer.previous()) << i;
    if (i % 2 == 0) {
      ASSERT_TRUE(buffer.update());
      EXPECT_EQ(buffer.previous(), newest);
      EXPECT_EQ(buffer.read(), i);
      newest = i;
    }
  }
}

TEST(QuadBuffer, HeldSnapshotsAreNeverWrittenUnderTheReader) {
  // The writer publishes as fast as it can; the reader checks after each update that the
  // snapshot it took before stays whole while it reads it again.
  Snapshot initial;
  initial.fill(0);
  QuadBuffer<Snapshot> buffer(initial);
  std::atomic<bool> done{false};
  std::thread writer = publish_in_sequence(buffer, done);
  std::uint64_t torn = 0, order = 0, updates = 0;
  auto check = [&] {
    if (!buffer.update()) return;
    ++updates;
    const Snapshot& now = buffer.read();
    const Snapshot& before = buffer.previous();
    if (!now.consistent() || !before.consistent()) ++torn;
    if (before.sequence >= now.sequence && now.sequence != 0) ++order;
  };
  while (!done.load(std::memory_order_acquire)) check();
  writer.join();
  check();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(order, 0u);
  EXPECT_GT(updates, 0u);
}

// ---------------------------------------------------------------- SeqLock

struct Pose {
  double position[3];
  double quaternion[4];
  std::uint64_t sequence;
};

struct Odd {  // 12 bytes: not a whole number of words
  float a, b, c;
};

TEST(SeqLock, LoadReturnsTheLastStore) {
  SeqLock<Pose> lock(Pose{{1, 2, 3}, {1, 0, 0, 0}, 0});
  EXPECT_EQ(lock.load().position[2], 3.0);
  lock.store(Pose{{4, 5, 6}, {0, 1, 0, 0}, 9});
  const Pose p = lock.load();
  EXPECT_EQ(p.position[0], 4.0);
  EXPECT_EQ(p.quaternion[1], 1.0);
  EXPECT_EQ(p.sequence, 9u);
}

TEST(SeqLock, RoundTripsValuesThatAreNotWholeWords) {
  SeqLock<Odd> lock;
  EXPECT_EQ(lock.load().c, 0.0f);
  lock.store(Odd{1.5f, -2.5f, 3.25f});
  const Odd o = lock.load();
  EXPECT_EQ(o.a, 1.5f);
  EXPECT_EQ(o.b, -2.5f);
  EXPECT_EQ(o.c, 3.25f);
}

TEST(SeqLock, ReadersNeverSeeATornOrOlderValue) {
  // 16 words, each derived from the sequence number: a copy that mixes two stores shows.
  struct Words {
    std::uint64_t sequence;
    std::array<std::uint64_t, 15> derived;
  };
  const auto make = [](std::uint64_t s) {
    Words w{s, {}};
    for (std::size_t i = 0; i < w.derived.size(); ++i) w.derived[i] = s * (i + 2) ^ 0x5555;
    return w;
  };
  // Each store is short, so tearing needs many of them to show up when the check is broken.
  constexpr std::uint64_t kSeqLockStores = 4 * kStressItems;
  SeqLock<Words> lock(make(0));
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t s = 1; s <= kSeqLockStores; ++s) lock.store(make(s));
    done.store(true, std::memory_order_release);
  });
  auto reader = [&](std::uint64_t& torn, std::uint64_t& backwards, std::uint64_t& last) {
    auto check = [&] {
      const Words w = lock.load();
      const Words expected = make(w.sequence);
      if (w.derived != expected.derived) ++torn;
      if (w.sequence < last) ++backwards;
      last = w.sequence;
    };
    while (!done.load(std::memory_order_acquire)) check();
    check();
  };
  std::uint64_t torn[2] = {}, backwards[2] = {}, last[2] = {};
  std::thread second([&] { reader(torn[1], backwards[1], last[1]); });
  reader(torn[0], backwards[0], last[0]);
  writer.join();
  second.join();
  for (int r = 0; r < 2; ++r) {
    EXPECT_EQ(torn[r], 0u) << "reader " << r;
    EXPECT_EQ(backwards[r], 0u) << "reader " << r;
    EXPECT_EQ(last[r], kSeqLockStores) << "reader " << r;
  }
}

// ---------------------------------------------------------------- SpscRing

TEST(SpscRing, CapacityIsRoundedUpToAPowerOfTwo) {
  EXPECT_EQ(SpscRing<int>(1).capacity(), 1u);
  EXPECT_EQ(SpscRing<int>(5).capacity(), 8u);
  EXPECT_EQ(SpscRing<int>(64).capacity(), 64u);
  EXPECT_THROW(SpscRing<int>(0), std::invalid_argument);
}

TEST(SpscRing, PushFailsWhenFullAndPopWhenEmpty) {
  SpscRing<int> ring(4);
  int out = -1;
  EXPECT_FALSE(ring.try_pop(out));
  EXPECT_EQ(out, -1);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_EQ(ring.size_approx(), 4u);
  EXPECT_FALSE(ring.try_push(99));
  EXPECT_TRUE(ring.try_pop(out));
  EXPECT_EQ(out, 0);
  EXPECT_TRUE(ring.try_push(4));  // the freed slot is usable again
  EXPECT_FALSE(ring.try_push(5));
  for (int expected = 1; expected <= 4; ++expected) {
    ASSERT_TRUE(ring.try_pop(out));
    EXPECT_EQ(out, expected);
  }
  EXPECT_FALSE(ring.try_pop(out));
  EXPECT_EQ(ring.size_approx(), 0u);
}

TEST(SpscRing, KeepsOrderAcrossManyWrapArounds) {
  SpscRing<std::uint64_t> ring(8);
  std::uint64_t next_in = 0, next_out = 0, out = 0;
  for (int round = 0; round < 1000; ++round) {
    const int pushes = 1 + round % 8;
    for (int i = 0; i < pushes; ++i) ASSERT_TRUE(ring.try_push(next_in++));
    while (ring.try_pop(out)) ASSERT_EQ(out, next_out++);
  }
  EXPECT_EQ(next_out, next_in);
}

TEST(SpscRing, DeliversEveryItemInOrderExactlyOnceAcrossThreads) {
  SpscRing<std::uint64_t> ring(64);
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kStressItems; ++i) {
      while (!ring.try_push(i)) std::this_thread::yield();
    }
  });
  std::uint64_t expected = 0, out_of_order = 0, item = 0;
  while (expected < kStressItems) {
    if (ring.try_pop(item)) {
      if (item != expected) ++out_of_order;
      expected = item + 1;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_FALSE(ring.try_pop(item)) << "an item arrived twice or beyond the last";
  EXPECT_EQ(ring.size_approx(), 0u);
}

// ---------------------------------------------------------------- no allocation

// The counter must see allocations, or "zero" below would prove nothing.
TEST(AllocationCounter, CountsEveryKindOfNewOnThisThreadOnly) {
  static void* volatile sink = nullptr;
  testing::AllocationCounter counter;
  EXPECT_EQ(counter.count(), 0u);
  sink = ::operator new(24);
  ::operator delete(sink);
  EXPECT_EQ(counter.count(), 1u);
  EXPECT_EQ(counter.bytes(), 24u);
  sink = ::operator new[](8, std::nothrow);
  ::operator delete[](sink);
  sink = ::operator new(256, std::align_val_t{128});
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(sink) % 128, 0u);
  ::operator delete(sink, std::align_val_t{128});
  EXPECT_EQ(counter.count(), 3u);
  {
    std::vector<int> v;
    v.push_back(1);
    sink = v.data();
  }
  EXPECT_EQ(counter.count(), 4u);

  std::uint64_t other_thread = 0;
  std::thread worker([&] {
    testing::AllocationCounter theirs;
    for (int i = 0; i < 1000; ++i) {
      sink = ::operator new(16);
      ::operator delete(sink);
    }
    other_thread = theirs.count();
  });
  worker.join();
  EXPECT_EQ(other_thread, 1000u);
  // Starting a std::thread allocates its state here, a few times at most: not the 1000.
  EXPECT_LT(counter.count(), 4u + 100u);
}

TEST(LockFreeExchange, HotPathsDoNotAllocate) {
  TripleBuffer<std::vector<double>> buffer(std::vector<double>(3000, 0.0));
  SeqLock<Pose> lock;
  SpscRing<Pose> ring(16);
  Pose pose{};
  double sum = 0;

  testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) {
    std::vector<double>& positions = buffer.write_buffer();
    for (std::size_t k = 0; k < positions.size(); ++k) positions[k] = i + 0.001 * static_cast<double>(k);
    buffer.publish();
    if (buffer.update()) sum += buffer.read()[1];

    pose.sequence = static_cast<std::uint64_t>(i);
    lock.store(pose);
    sum += static_cast<double>(lock.load().sequence);

    ring.try_push(pose);
    Pose popped{};
    if (ring.try_pop(popped)) sum += static_cast<double>(popped.sequence);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

}  // namespace
}  // namespace tactus
