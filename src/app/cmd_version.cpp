#include <Eigen/Core>
#include <cstdio>

#include "app/commands.hpp"
#include "core/version.hpp"

namespace tactus::app {

Action add_version(CLI::App&) {
  return [] {
    std::printf("tactus %s (%s build, Eigen %d.%d.%d)\n", kVersion, kBuildType,
                EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
    return 0;
  };
}

}  // namespace tactus::app
