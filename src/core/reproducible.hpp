#pragma once
// Results that do not depend on the machine. Eigen cuts its dense matrix products into blocks
// sized from the CPU's cache sizes, read at run time: the same product then sums in another
// order on a CPU with another L1 or L2, and a lockstep run (a recording, its replay) differs
// in the last bits from one machine to the next. The local patch models solve such products at
// the haptic rate. Fixed sizes make every machine sum alike.
namespace tactus {

/// The cache sizes Eigen blocks its products for, whatever the CPU: 32 KiB L1, 1 MiB L2,
/// 32 MiB L3 (a common x86-64 server core). Idempotent; call before any computation (the
/// `tactus` command and run_session do).
void fix_dense_blocking();

/// BLAS (OpenBLAS, under CHOLMOD's factorizations) on the calling thread alone, unless
/// OPENBLAS_NUM_THREADS says otherwise. The engine already runs a thread per loop: BLAS's own
/// threads fought them for the cores (the liver scene's worst simulation step took 9–17 s
/// instead of 0.5 s on two cores), and a factorization sums in another order with another
/// thread count, so a recording would not replay bit for bit. Returns the BLAS threads now
/// in effect, or 0 where the loaded BLAS is not OpenBLAS (left as it is). Call before any
/// computation (the `tactus` command and run_session do).
int fix_blas_threads();

}  // namespace tactus
