#pragma once
// A progress bar for long operations. It draws when stderr is a terminal and CI is not
// set; on a pipe or into a file (CI not set) it writes a line at each tenth done once the
// operation has lasted two seconds, so a phase of minutes is never silent; under CI nothing.
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
  bool lines_;                ///< not a terminal: a line per tenth
  std::size_t last_tenth_ = 0;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace tactus
