#pragma once
// A progress bar for long operations. It draws only when stderr is a terminal and
// CI is not set, so logs stay clean.
#include <chrono>
#include <cstddef>
#include <string>

namespace tactus {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(std::size_t done);
  void finish();
  [[nodiscard]] bool visible() const { return visible_; }

  /// True when progress output makes sense: stderr is a tty and $CI is unset.
  static bool terminal_attached();

 private:
  std::string label_;
  std::size_t total_;
  bool visible_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace tactus
