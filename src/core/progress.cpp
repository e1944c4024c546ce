#include "core/progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace tactus {

bool Progress::terminal_attached() {
  const char* ci = std::getenv("CI");
  return isatty(STDERR_FILENO) != 0 && (ci == nullptr || *ci == '\0');
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total == 0 ? 1 : total),
      visible_(terminal_attached()),
      lines_(!visible_ && (std::getenv("CI") == nullptr || *std::getenv("CI") == '\0')),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

void Progress::update(std::size_t done) {
  if (finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (lines_) {
    const std::size_t tenth = 10 * (done > total_ ? total_ : done) / total_;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (tenth <= last_tenth_ || elapsed < 2.0) return;
    last_tenth_ = tenth;
    const double frac = static_cast<double>(tenth) / 10.0;
    std::fprintf(stderr, "%s: %3.0f%% (%.1f s, %.1f s left)\n", label_.c_str(), 100.0 * frac, elapsed,
                 elapsed * (1.0 - frac) / frac);
    std::fflush(stderr);
    return;
  }
  if (!visible_) return;
  if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double frac = static_cast<double>(done > total_ ? total_ : done) / static_cast<double>(total_);
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(frac * kWidth);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double left = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3.0f%%  %.1fs left ", label_.c_str(), filled,
               "##############################", kWidth - filled, "", 100.0 * frac, left);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!visible_ || finished_) return;
  update(total_);
  finished_ = true;
  std::fputc('\n', stderr);
}

}  // namespace tactus
