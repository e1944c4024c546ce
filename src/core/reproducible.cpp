#include "core/reproducible.hpp"

#include <Eigen/Core>

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>

namespace tactus {

void fix_dense_blocking() {
  // Once per process: Eigen keeps the sizes in statics that its products read unguarded.
  static std::once_flag once;
  std::call_once(once, [] {
    constexpr std::ptrdiff_t kL1 = 32 * 1024, kL2 = 1024 * 1024, kL3 = 32 * 1024 * 1024;
    Eigen::setCpuCacheSizes(kL1, kL2, kL3);
  });
}

int fix_blas_threads() {
  // Looked up at run time: the engine links whichever BLAS Debian's alternatives provide.
  using SetThreads = void (*)(int);
  using GetThreads = int (*)();
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (!set || !get) return 0;
  const char* chosen = std::getenv("OPENBLAS_NUM_THREADS");
  if (!chosen || !*chosen) set(1);
  return get();
}

}  // namespace tactus
