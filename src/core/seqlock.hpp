#pragma once
// Sequence lock for small plain values (a device pose, a few parameters): one writer that
// never waits, any number of readers that retry while a store is in progress.
//
// Why no data race: the classic seqlock copies the value with plain loads while the writer
// may be storing, which is a data race (undefined behaviour) in the C++ memory model even
// though the result is discarded. Here the value lives in an array of atomic words:
//  - store() bumps the counter to odd (relaxed), writes every word with a release store,
//    then bumps the counter to even with a release store;
//  - load() reads the counter with acquire, every word with acquire, then the counter again.
// A reader that sees any word of a store in progress synchronizes with that word's release
// store, so the odd counter value written before it is visible to the second counter read,
// which then differs from the first and the copy is retried. A reader whose first counter
// read sees a finished store sees all its words. Acquire/release per word costs nothing on
// x86 and avoids standalone fences, which ThreadSanitizer does not model.
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <thread>
#include <type_traits>

namespace tactus {

template <class T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>, "SeqLock<T> copies T bytewise: T must be trivially copyable");
  static_assert(sizeof(T) <= 256, "SeqLock<T> is meant for small values; use TripleBuffer for large ones");

 public:
  SeqLock() : SeqLock(T{}) {}
  explicit SeqLock(const T& initial) { write_words(initial); }

  SeqLock(const SeqLock&) = delete;
  SeqLock& operator=(const SeqLock&) = delete;

  /// Writer thread only (one writer). Never waits.
  void store(const T& value) {
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1, std::memory_order_relaxed);
    write_words(value);
    sequence_.store(s + 2, std::memory_order_release);
  }

  /// Any thread. Retries while a store is in progress, so it returns a value that was
  /// stored as a whole: the newest one, or one that was newest during the call.
  [[nodiscard]] T load() const {
    std::array<Word, kWords> words;
    for (;;) {
      const std::uint64_t before = sequence_.load(std::memory_order_acquire);
      if ((before & 1) == 0) {
        for (std::size_t i = 0; i < kWords; ++i) words[i] = words_[i].load(std::memory_order_acquire);
        if (sequence_.load(std::memory_order_relaxed) == before) return from_words(words);
      }
      relax();
    }
  }

 private:
  using Word = std::uint64_t;
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(Word) - 1) / sizeof(Word);
  static constexpr std::size_t kCacheLine = 64;

  void write_words(const T& value) {
    std::array<Word, kWords> words{};
    std::memcpy(words.data(), &value, sizeof(T));
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(words[i], std::memory_order_release);
  }

  static T from_words(const std::array<Word, kWords>& words) {
    std::array<std::byte, sizeof(T)> bytes;
    std::memcpy(bytes.data(), words.data(), sizeof(T));
    return std::bit_cast<T>(bytes);
  }

  static void relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
  }

  alignas(kCacheLine) std::atomic<std::uint64_t> sequence_{0};
  std::array<std::atomic<Word>, kWords> words_{};
};

}  // namespace tactus
