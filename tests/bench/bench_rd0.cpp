// RD0 throughput at φ = 0.84 (harmonic, skin 0.3, Δt = 0.2, γ̇ = 1e-4), as particle-steps
// per second ("items_per_second") and particle force evaluations per second.
// The state is first relaxed for 2000 steps (untimed) so that the timed steps see a
// sheared steady-state-like configuration rather than the random start.
#include <benchmark/benchmark.h>

#include "jamsim/dynamics/force_field.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/dynamics/replica.hpp"

using namespace jamsim;

static void BM_Rd0(benchmark::State& state) {
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = 0.84;
    p.rate = 1e-4;
    const auto integ = state.range(1) ? Integrator::Heun : Integrator::Euler;
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(ModelParams{1.0, integ});
    for (int s = 0; s < 2000; ++s) {
        ff.compute(sys);
        model.advance(sys, ff, p.dt, p.rate);
    }
    const auto builds0 = ff.list().builds();
    for (auto _ : state) {
        ff.compute(sys, Tally::ForcesOnly);  // as on the steps between samples
        model.advance(sys, ff, p.dt, p.rate);
    }
    const double steps = static_cast<double>(state.iterations());
    const double evals_per_step = integ == Integrator::Heun ? 2.0 : 1.0;
    state.SetItemsProcessed(static_cast<std::int64_t>(steps) * p.n);
    state.counters["force_evals_per_s"] = benchmark::Counter(
        steps * evals_per_step * static_cast<double>(p.n), benchmark::Counter::kIsRate);
    state.counters["steps_per_rebuild"] =
        steps / static_cast<double>(std::max<std::size_t>(1, ff.list().builds() - builds0));
    state.counters["pairs_per_particle"] =
        static_cast<double>(ff.list().size()) / static_cast<double>(p.n);
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

BENCHMARK_MAIN();
