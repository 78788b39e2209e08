#pragma once
// Threads inside one replica (OpenMP). A replica's results are the same bits on any number
// of threads: every threaded loop either writes each element from one iteration alone, or
// combines its terms in an order fixed by the system (list order, particle order), never by
// the thread count. The count is OpenMP's (OMP_NUM_THREADS, or set_kernel_threads from
// --threads); jamsim starts at 1 thread when neither says otherwise.
#include <cstddef>
#include <cstdint>

#include <omp.h>

namespace jamsim {

/// Threads a kernel loop may use: OpenMP's nthreads-var, within its thread-limit-var
/// (OMP_THREAD_LIMIT=1 with OMP_NUM_THREADS=2 runs one thread, which the log called 2).
inline int kernel_threads() {
    const int limit = omp_get_thread_limit();
    const int wanted = omp_get_max_threads();
    return limit > 0 && limit < wanted ? limit : wanted;
}

/// Set the threads of every later kernel loop on this process (>= 1).
inline void set_kernel_threads(int threads) { omp_set_num_threads(threads); }

/// Wall time the calling thread spent in parallel regions it opened (TimedRegion): a
/// diagnostic for the benchmarks, which subtract it from a step's time to get the step's
/// serial part. Per thread (thread_local), so it needs no synchronisation.
struct RegionClock {
    double seconds = 0.0;
    std::int64_t regions = 0;
};
inline RegionClock& region_clock() {
    static thread_local RegionClock clock;
    return clock;
}

/// Adds its lifetime to region_clock() when `active` (declare it just before a parallel
/// region that really runs on several threads). Two omp_get_wtime calls, ~50 ns.
class TimedRegion {
  public:
    explicit TimedRegion(bool active = true) : start_(active ? omp_get_wtime() : -1.0) {}
    ~TimedRegion() {
        if (start_ < 0.0) return;
        RegionClock& clock = region_clock();
        clock.seconds += omp_get_wtime() - start_;
        ++clock.regions;
    }
    TimedRegion(const TimedRegion&) = delete;
    TimedRegion& operator=(const TimedRegion&) = delete;

  private:
    double start_;
};

/// Loops shorter than this run on one thread: a parallel region costs a few µs.
inline constexpr std::size_t kThreadedLoopMin = 4096;

/// body(i) for i in [0, n), split over the kernel's threads when there are several and the
/// loop is long enough. For loops whose iterations write disjoint elements: the result is
/// the same whatever the split.
template <class Body> void parallel_for(std::size_t n, Body&& body) {
    if (n >= kThreadedLoopMin && kernel_threads() > 1) {
        const auto count = static_cast<long>(n);
        const TimedRegion timed;
#pragma omp parallel for schedule(static)
        for (long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
    } else {
        for (std::size_t i = 0; i < n; ++i) body(i);
    }
}

/// body(b) for each of `count` large pieces of work (blocks of a fixed decomposition),
/// split over the kernel's threads whenever there are several of both. For pieces that write
/// disjoint elements: the result is the same whatever the split.
template <class Body> void parallel_for_blocks(std::size_t count, Body&& body) {
    if (count > 1 && kernel_threads() > 1) {
        const auto blocks = static_cast<long>(count);
        const TimedRegion timed;
#pragma omp parallel for schedule(static)
        for (long b = 0; b < blocks; ++b) body(static_cast<std::size_t>(b));
    } else {
        for (std::size_t b = 0; b < count; ++b) body(b);
    }
}

}  // namespace jamsim
