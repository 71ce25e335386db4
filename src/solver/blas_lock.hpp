#pragma once
// One lock around every call into BLAS: UMFPACK's and CHOLMOD's dense kernels. The serial
// OpenBLAS that scripts/install-deps.sh installs (Debian's libopenblas0-serial, built without
// OpenBLAS's USE_LOCKING) shares its work buffers between threads unguarded, so two sweep
// workers inside it at once corrupt each other's factors (measured: a two-thread UMFPACK sweep
// of the tripteron wrong in the third digit at some poses, tests/test_sweep.cpp). KLU and Eigen's
// solvers call no BLAS and take no lock, so robots on the default solver keep their threads.
#include <mutex>

namespace stiffmsa::detail {

std::mutex& blas_mutex();

}  // namespace stiffmsa::detail
