#pragma once
// Threads inside one replica (OpenMP). A replica's results are the same bits on any number
// of threads: every threaded loop either writes each element from one iteration alone, or
// combines its terms in an order fixed by the system (list order, particle order), never by
// the thread count. The count is OpenMP's (OMP_NUM_THREADS, or set_kernel_threads from
// --threads); jamsim starts at 1 thread when neither says otherwise.
#include <cstddef>

#include <omp.h>

namespace jamsim {

/// Threads a kernel loop may use (OpenMP's nthreads-var; 1 when OpenMP says so).
inline int kernel_threads() { return omp_get_max_threads(); }

/// Set the threads of every later kernel loop on this process (>= 1).
inline void set_kernel_threads(int threads) { omp_set_num_threads(threads); }

/// Loops shorter than this run on one thread: a parallel region costs a few µs.
inline constexpr std::size_t kThreadedLoopMin = 4096;

/// body(i) for i in [0, n), split over the kernel's threads when there are several and the
/// loop is long enough. For loops whose iterations write disjoint elements: the result is
/// the same whatever the split.
template <class Body>
void parallel_for(std::size_t n, Body&& body) {
    if (n >= kThreadedLoopMin && kernel_threads() > 1) {
        const auto count = static_cast<long>(n);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
    } else {
        for (std::size_t i = 0; i < n; ++i) body(i);
    }
}

/// body(b) for each of `count` large pieces of work (blocks of a fixed decomposition),
/// split over the kernel's threads whenever there are several of both. For pieces that write
/// disjoint elements: the result is the same whatever the split.
template <class Body>
void parallel_for_blocks(std::size_t count, Body&& body) {
    if (count > 1 && kernel_threads() > 1) {
        const auto blocks = static_cast<long>(count);
#pragma omp parallel for schedule(static)
        for (long b = 0; b < blocks; ++b) body(static_cast<std::size_t>(b));
    } else {
        for (std::size_t b = 0; b < count; ++b) body(b);
    }
}

} // namespace jamsim
