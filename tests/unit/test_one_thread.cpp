// On one thread a replica opens no OpenMP parallel region. Even a region of one thread (an
// `if (false)` clause) ends in libgomp's team barrier, whose last arrival wakes the waiters
// with a futex system call: one or two per force evaluation cost a replica of 1024 disks a
// quarter of its time, and tiny replicas (RAND quenches of 16-64 disks) two thirds.
//
// GCC 12 enters every parallel region through one of libgomp's GOMP_parallel* functions:
// GOMP_parallel (`parallel`, and `parallel for` with a static schedule, which is all jamsim
// uses), GOMP_parallel_sections, GOMP_parallel_loop_* (other schedules). This executable
// defines those, so the kernel's calls (linked statically) and the libraries' (CHOLMOD's, for
// one) come here, are counted, and go on to libgomp's.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>

#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/run/replica.hpp"

namespace {
std::atomic<long> g_regions{0};  // parallel regions opened since the last reset

/// libgomp's own `name`, counting one region.
template <class Entry> Entry counted_entry(const char* name) {
    g_regions.fetch_add(1, std::memory_order_relaxed);
    void* symbol = dlsym(RTLD_NEXT, name);
    Entry entry = nullptr;
    std::memcpy(&entry, &symbol, sizeof entry);
    return entry;
}
using Body = void (*)(void*);
}  // namespace

extern "C" {
void GOMP_parallel(Body fn, void* data, unsigned threads, unsigned flags);
void GOMP_parallel_sections(Body fn, void* data, unsigned threads, unsigned count, unsigned flags);
void GOMP_parallel_loop_static(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                               unsigned flags);
void GOMP_parallel_loop_dynamic(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                                unsigned flags);
void GOMP_parallel_loop_guided(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                               unsigned flags);
void GOMP_parallel_loop_runtime(Body fn, void* data, unsigned threads, long start, long end, long incr, unsigned flags);

void GOMP_parallel(Body fn, void* data, unsigned threads, unsigned flags) {
    counted_entry<decltype(&GOMP_parallel)>("GOMP_parallel")(fn, data, threads, flags);
}
void GOMP_parallel_sections(Body fn, void* data, unsigned threads, unsigned count, unsigned flags) {
    counted_entry<decltype(&GOMP_parallel_sections)>("GOMP_parallel_sections")(fn, data, threads, count, flags);
}
void GOMP_parallel_loop_static(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                               unsigned flags) {
    counted_entry<decltype(&GOMP_parallel_loop_static)>("GOMP_parallel_loop_static")(fn, data, threads, start, end,
                                                                                     incr, chunk, flags);
}
void GOMP_parallel_loop_dynamic(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                                unsigned flags) {
    counted_entry<decltype(&GOMP_parallel_loop_dynamic)>("GOMP_parallel_loop_dynamic")(fn, data, threads, start, end,
                                                                                       incr, chunk, flags);
}
void GOMP_parallel_loop_guided(Body fn, void* data, unsigned threads, long start, long end, long incr, long chunk,
                               unsigned flags) {
    counted_entry<decltype(&GOMP_parallel_loop_guided)>("GOMP_parallel_loop_guided")(fn, data, threads, start, end,
                                                                                     incr, chunk, flags);
}
void GOMP_parallel_loop_runtime(Body fn, void* data, unsigned threads, long start, long end, long incr,
                                unsigned flags) {
    counted_entry<decltype(&GOMP_parallel_loop_runtime)>("GOMP_parallel_loop_runtime")(fn, data, threads, start, end,
                                                                                       incr, flags);
}
}

namespace jamsim {
namespace {

struct ThreadCount {
    explicit ThreadCount(int t) : before(kernel_threads()) { set_kernel_threads(t); }
    ~ThreadCount() { set_kernel_threads(before); }
    int before;
};

/// A short replica of `model` at N disks (past 4096 the kernel's loops have several blocks): sheared models a strain of 0.01 at γ̇ = 1e-3, rate-0
/// protocols a time of 2 τ or their own quench, QS and SHEARED three strain steps.
ReplicaParams short_replica(const ModelInfo& model, std::int64_t n) {
    ReplicaParams p;
    p.model = std::string(model.name);
    p.n = n;
    p.phi = 0.86;
    p.rate = 1e-3;
    p.strain = 0.01;
    p.sample_interval = 0.005;
    p.cooling_time = 2.0;
    p.strain_step = 1e-3;
    if (p.model == "QS" || p.model == "SHEARED") {
        p.rate = 0;
        p.strain = 3e-3;
        p.sample_interval = 1e-3;
    } else if (p.model == "RAND" || p.model == "COMPRESS" || p.model == "COOL" || p.model == "COOL_COMPRESS") {
        p.rate = 0;
        p.time = 2.0;
        p.sample_interval = 1.0;
    }
    return p;
}

TEST(OneThread, CountsTheRegionsOfTwoThreads) {
    // The count itself: two threads on 8192 disks (two force blocks) open regions.
    const ThreadCount count(2);
    ReplicaParams p;
    p.n = 8192;
    p.strain = 0.002;
    p.sample_interval = 0.001;
    p.rate = 1e-3;
    g_regions = 0;
    run_replica(p);
    EXPECT_GT(g_regions.load(), 0);
}

/// A size past one block of the kernel's loops: 8192 disks for dynamics, 4608 for a
/// minimisation, 256 for a protocol that ends in a φ_J search (tens of seconds at 4608).
std::int64_t large(const ModelInfo& model) {
    if (model.kind == ModelKind::Dynamics) return 8192;
    return model.open_ended ? 256 : 4608;
}

TEST(OneThread, NoModelOpensAParallelRegion) {
    const ThreadCount count(1);
    for (const ModelInfo& model : models())
        for (const std::int64_t n : {std::int64_t{64}, large(model)}) {
            SCOPED_TRACE(std::string(model.name) + " N = " + std::to_string(n));
            const ReplicaParams p = short_replica(model, n);
            g_regions = 0;
            run_replica(p);
            EXPECT_EQ(g_regions.load(), 0);
        }
}

TEST(OneThread, SmallReplicasOpenNoRegionOnTwoThreads) {
    // Below one block of the kernel's loops (4096 disks) two threads have nothing to share: a
    // rank lent a second core runs a small replica on one, without regions.
    const ThreadCount count(2);
    for (const ModelInfo& model : models()) {
        SCOPED_TRACE(std::string(model.name) + " N = 256 on 2 threads");
        const ReplicaParams p = short_replica(model, 256);
        g_regions = 0;
        run_replica(p);
        EXPECT_EQ(g_regions.load(), 0);
    }
}

}  // namespace
}  // namespace jamsim
