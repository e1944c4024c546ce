#pragma once
// Wait-free hand-over of the newest snapshot from one writer thread to one reader thread.
// Three slots: the writer fills its back slot, the reader reads its front slot, and the
// third (middle) slot is swapped with either side through one atomic byte, so neither side
// ever waits, copies or allocates. The reader may skip snapshots; it never sees a torn one.
// QuadBuffer adds a fourth slot in which the reader keeps the snapshot before its newest
// until its next update(): a reader that refers to snapshots in place instead of copying
// them can still read the one it is replacing in the frame it switches.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace tactus {

/// Held: how many older snapshots the reader keeps (0: a triple buffer, 1: a quad buffer).
template <class T, int Held>
class SnapshotBuffer {
  static_assert(Held == 0 || Held == 1);

 public:
  /// Every slot value-initialized.
  SnapshotBuffer() = default;
  /// Every slot a copy of `initial`: pre-size containers here so that neither loop
  /// allocates later.
  explicit SnapshotBuffer(const T& initial) {
    for (Slot& s : slots_) s.value = initial;
  }

  SnapshotBuffer(const SnapshotBuffer&) = delete;
  SnapshotBuffer& operator=(const SnapshotBuffer&) = delete;

  // --- writer thread only ---

  /// The slot to fill before publish(). After a publish it holds an older snapshot (or the
  /// initial value), not the one just published: overwrite every field that matters.
  [[nodiscard]] T& write_buffer() { return slots_[back_].value; }

  /// Makes the write buffer the newest snapshot and takes the middle slot as the next one.
  void publish() {
    // acq_rel: release hands our writes to the reader; acquire makes sure the reader has
    // finished with the slot we take back before we overwrite it.
    const std::uint8_t previous = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = static_cast<std::uint8_t>(previous & kIndexMask);
  }

  // --- reader thread only ---

  /// Takes the newest published snapshot if there is one the reader has not seen yet;
  /// returns whether read() changed.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    // The slot handed back to the writer: the front one, or with a held slot the held one
    // (the front one becomes the held).
    const std::uint8_t released = Held ? held_ : front_;
    const std::uint8_t previous = middle_.exchange(released, std::memory_order_acq_rel);
    if constexpr (Held == 1) held_ = front_;
    front_ = static_cast<std::uint8_t>(previous & kIndexMask);
    return true;
  }

  /// The snapshot taken by the last update() (the initial value before any).
  [[nodiscard]] const T& read() const { return slots_[front_].value; }
  /// QuadBuffer: the snapshot read() gave before the last update(), valid until the next.
  [[nodiscard]] const T& previous() const
    requires(Held == 1)
  {
    return slots_[held_].value;
  }

 private:
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;  // set by publish, cleared by update
  static constexpr std::size_t kCacheLine = 64;

  // Each slot on its own cache lines, so the two threads do not share lines while working.
  struct alignas(kCacheLine) Slot {
    T value{};
  };

  std::array<Slot, 3 + Held> slots_{};
  alignas(kCacheLine) std::atomic<std::uint8_t> middle_{1};
  alignas(kCacheLine) std::uint8_t back_ = 0;  // writer's
  alignas(kCacheLine) std::uint8_t front_ = 2;  // reader's
  std::uint8_t held_ = 3;  // reader's (QuadBuffer)
};

template <class T>
using TripleBuffer = SnapshotBuffer<T, 0>;
template <class T>
using QuadBuffer = SnapshotBuffer<T, 1>;

}  // namespace tactus
