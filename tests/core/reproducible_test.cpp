// Eigen's dense products block by the CPU's cache sizes, so the same product sums in another
// order on another CPU (the patch models' solves differed in the last bits between two 2-core
// EPYC machines, and with them every recorded force). fix_dense_blocking() makes every machine
// block alike; tests/scenarios/replay_regression_test.cpp checks the forces end to end.
#include "core/reproducible.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tactus
