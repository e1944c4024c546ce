// Progress output: a line per tenth when stderr is not a terminal, nothing under CI.
#include "core/progress.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

namespace tactus {
namespace {

std::string run_phase() {
  ::testing::internal::CaptureStderr();
  {
    Progress p("creep of upper_leg", 10);
    p.update(1);  // before two seconds: silent
    std::this_thread::sleep_for(std::chrono::milliseconds(2100));
    for (std::size_t i = 2; i <= 10; ++i) p.update(i);
  }
  return ::testing::internal::GetCapturedStderr();
}

TEST(Progress, ALinePerTenthWhenStderrIsNoTerminal) {
  ::unsetenv("CI");
  const std::string out = run_phase();
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 9) << out;
  EXPECT_NE(out.find("creep of upper_leg:  20% ("), std::string::npos) << out;
  EXPECT_NE(out.find("creep of upper_leg: 100% ("), std::string::npos) << out;
  EXPECT_EQ(out.find("  10%"), std::string::npos) << out;
}

TEST(Progress, NothingUnderCi) {
  ::setenv("CI", "true", 1);
  EXPECT_EQ(run_phase(), "");
}

}  // namespace
}  // namespace tactus
