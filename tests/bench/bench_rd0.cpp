// RD0 throughput at φ = 0.84 (harmonic, skin 0.3, Δt = 0.2, γ̇ = 1e-4), as particle-steps
// per second ("items_per_second") and particle force evaluations per second.
// The state is first relaxed for 2000 steps (untimed) so that the timed steps see a
// sheared steady-state-like configuration rather than the random start.
#include <benchmark/benchmark.h>

#include "jamsim/force/force_field.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/run/replica.hpp"
#include "jamsim/dynamics/sllod.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/parallel/threads.hpp"

using namespace jamsim;

static void BM_Rd0(benchmark::State& state) {
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = 0.84;
    p.rate = 1e-4;
    const std::string integ = state.range(1) ? "heun" : "euler";
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(ReplicaParams{.integrator = integ, .kd = 1.0});
    for (int s = 0; s < 2000; ++s) {
        ff.compute(sys);
        model.advance(sys, ff, p.dt, p.rate, 0);
    }
    const auto builds0 = ff.list().builds();
    for (auto _ : state) {
        ff.compute(sys, Tally::ForcesOnly);  // as on the steps between samples
        model.advance(sys, ff, p.dt, p.rate, 0);
    }
    const double steps = static_cast<double>(state.iterations());
    const double evals_per_step = integ == "heun" ? 2.0 : 1.0;
    state.SetItemsProcessed(static_cast<std::int64_t>(steps) * p.n);
    state.counters["force_evals_per_s"] =
        benchmark::Counter(steps * evals_per_step * static_cast<double>(p.n), benchmark::Counter::kIsRate);
    state.counters["steps_per_rebuild"] =
        steps / static_cast<double>(std::max<std::size_t>(1, ff.list().builds() - builds0));
    state.counters["pairs_per_particle"] = static_cast<double>(ff.list().size()) / static_cast<double>(p.n);
}
BENCHMARK(BM_Rd0)
    ->ArgNames({"N", "heun"})
    ->Args({1024, 0})
    ->Args({16384, 0})
    ->Args({65536, 0})
    ->Args({1024, 1})
    ->Args({65536, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

// RD0 (Euler) on T threads inside the replica: particle-steps per second; the ratio to the
// T = 1 row of the same N is the speed-up (the results are the same bits on any T). On a
// machine of fewer cores, filter the rows that fit (--benchmark_filter='threads:(1|2)/').
static void BM_Rd0Threads(benchmark::State& state) {
    const int before = kernel_threads();
    set_kernel_threads(static_cast<int>(state.range(1)));
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = 0.84;
    p.rate = 1e-4;
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(ReplicaParams{.integrator = "euler", .kd = 1.0});
    for (int s = 0; s < 2000; ++s) {  // untimed, as BM_Rd0
        ff.compute(sys);
        model.advance(sys, ff, p.dt, p.rate, 0);
    }
    const RegionClock at_start = region_clock();
    const double start = omp_get_wtime();
    for (auto _ : state) {
        ff.compute(sys, Tally::ForcesOnly);
        model.advance(sys, ff, p.dt, p.rate, 0);
    }
    const double wall = omp_get_wtime() - start;
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
    // The serial part S of a step: its wall time outside parallel regions (TimedRegion).
    // With R the time inside them on T threads, Amdahl's serial fraction is S / (S + T R)
    // (S + T R: the one-thread time if the regions scaled perfectly). On one thread no
    // region opens: S is the whole step and the fraction 1.
    const double steps = static_cast<double>(state.iterations());
    const double inside = region_clock().seconds - at_start.seconds, serial = wall - inside;
    state.counters["serial_us"] = 1e6 * serial / steps;
    state.counters["serial_fraction"] = serial / (serial + static_cast<double>(state.range(1)) * inside);
    // Parallel regions opened per step: each costs a fork and a join (a few µs on 16 threads).
    state.counters["regions_per_step"] = static_cast<double>(region_clock().regions - at_start.regions) / steps;
    set_kernel_threads(before);
}
BENCHMARK(BM_Rd0Threads)
    ->ArgNames({"N", "threads"})
    ->ArgsProduct({{16384, 65536, 262144}, {1, 2, 4, 8, 16}})  // here: --benchmark_filter='threads:(1|2)/'
    ->UseRealTime()                                            // wall-clock time: the threads share the step
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

// Massive RD (SLLOD, drag on the velocity relative to the shear profile) at φ = 0.84,
// Δt = 0.1, m = 1, k_d = 1: the workload LAMMPS runs with fix nve + fix langevin 0 0 1.0 and a
// temp/deform bias. Both evaluate forces once per step: jamsim with its second-order
// splitting (exact drag), LAMMPS with velocity Verlet; as in the driver, the step loop needs
// no separate evaluation because advance() leaves the new forces in place.
static void BM_RdMassive(benchmark::State& state) {
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = 0.84;
    p.rate = 1e-4;
    p.dt = 0.1;
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    ReplicaParams params{.integrator = "heun", .kd = 1.0};
    params.mass = 1.0;
    Sllod model(params, Damping::RD);
    ff.compute(sys);
    model.prepare(sys, ff, p.rate);
    for (int s = 0; s < 2000; ++s) model.advance(sys, ff, p.dt, p.rate, 0);  // untimed
    for (auto _ : state) model.advance(sys, ff, p.dt, p.rate, 0);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
}
BENCHMARK(BM_RdMassive)->ArgName("N")->Arg(1024)->Arg(16384)->Unit(benchmark::kMillisecond)->MinTime(2.0);

BENCHMARK_MAIN();

// CG (the default minimiser) on T threads: 100 iterations of the RAND quench of N disks at
// φ = 0.86 from the same random start each time, as particle force evaluations per second
// ("items_per_second"); the ratio to the T = 1 row of the same N is the speed-up (the same
// bits on any T). The minimisation is cut at 100 iterations: its early, far-from-minimum
// part, where each iteration costs most.
static void BM_CgThreads(benchmark::State& state) {
    const int before = kernel_threads();
    set_kernel_threads(static_cast<int>(state.range(1)));
    const System start = random_system(state.range(0), 0.86, SizeMix{}, 1, 0);
    const auto minimizer = make_minimizer("cg");
    MinimizeCriteria criteria;
    criteria.max_iterations = 100;
    std::int64_t evaluations = 0;
    for (auto _ : state) {
        System sys = start;
        ForceField ff(potential::make_soft_sphere(2.0), 0.3);
        evaluations += minimizer->minimize(sys, ff, criteria).force_evaluations;
    }
    state.SetItemsProcessed(evaluations * state.range(0));
    set_kernel_threads(before);
}
BENCHMARK(BM_CgThreads)
    ->ArgNames({"N", "threads"})
    ->ArgsProduct({{16384, 65536}, {1, 2, 4, 8, 16}})  // here: --benchmark_filter='threads:(1|2)/'
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
