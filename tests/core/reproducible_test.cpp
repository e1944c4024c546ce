// Eigen's dense products block by the CPU's cache sizes, so the same product sums in another
// order on another CPU (the patch models' solves differed in the last bits between two 2-core
// EPYC machines, and with them every recorded force). fix_dense_blocking() makes every machine
// block alike; tests/scenarios/replay_regression_test.cpp checks the forces end to end.
#include "core/reproducible.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdlib>

#include <Eigen/Core>

namespace tactus {
namespace {

TEST(Reproducible, EveryMachineBlocksForTheSameCacheSizes) {
  Eigen::setCpuCacheSizes(48 * 1024, 2 * 1024 * 1024, 384 * 1024 * 1024);  // as this CPU reports
  fix_dense_blocking();
  EXPECT_EQ(Eigen::l1CacheSize(), 32 * 1024);
  EXPECT_EQ(Eigen::l2CacheSize(), 1024 * 1024);
  EXPECT_EQ(Eigen::l3CacheSize(), 32 * 1024 * 1024);
}

TEST(Reproducible, BlasRunsOnTheCallingThreadUnlessTheUserChoseOtherwise) {
  // The engine loads OpenBLAS through CHOLMOD; this test loads it itself.
  if (!dlopen("libopenblas.so.0", RTLD_NOW | RTLD_GLOBAL)) GTEST_SKIP() << "OpenBLAS is not installed";
  const auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  ASSERT_NE(set, nullptr);
  set(4);
  unsetenv("OPENBLAS_NUM_THREADS");
  EXPECT_EQ(fix_blas_threads(), 1);
  set(2);  // what OpenBLAS does at load time with OPENBLAS_NUM_THREADS=2
  setenv("OPENBLAS_NUM_THREADS", "2", 1);
  EXPECT_EQ(fix_blas_threads(), 2);
}

}  // namespace
}  // namespace tactus
