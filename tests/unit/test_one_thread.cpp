// On one thread a replica opens no OpenMP parallel region. Even a region of one thread (an
// `if (false)` clause) ends in libgomp's team barrier, whose last arrival wakes the waiters
// with a futex system call: one or two per force evaluation cost a replica of 1024 disks a
// quarter of its time, and tiny replicas (RAND quenches of 16-64 disks) two thirds.
//
// GOMP_parallel is GCC's entry for every `#pragma omp parallel` (with or without `for`);
// this executable defines it, so the kernel's calls (linked statically) come here, are
// counted and go on to libgomp's.
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
using ParallelEntry = void (*)(void (*)(void*), void*, unsigned, unsigned);
}  // namespace

extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags);
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
    static const ParallelEntry real = [] {
        void* symbol = dlsym(RTLD_NEXT, "GOMP_parallel");
        ParallelEntry entry = nullptr;
        std::memcpy(&entry, &symbol, sizeof entry);
        return entry;
    }();
    g_regions.fetch_add(1, std::memory_order_relaxed);
    real(fn, data, num_threads, flags);
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

}  // namespace
}  // namespace jamsim
