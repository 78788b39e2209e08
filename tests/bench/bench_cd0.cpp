// CD0 against RD0 per step at φ = 0.84 (harmonic, Euler, Δt = 0.2, γ̇ = 1e-4): particle-steps
// per second and the Krylov iterations per solve. Solver options come from the command line
// through PETSc's options database, e.g.  jamsim_bench_cd0 -cd0_pc_type icc
#include <benchmark/benchmark.h>
#include <petscsys.h>

#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

template <class ModelT> static void run_model(benchmark::State& state, const char* solver = "petsc") {
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = 0.84;
    p.rate = 1e-4;
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    ReplicaParams params = p;
    params.solver = solver;
    ModelT model(params);
    for (int s = 0; s < 1000; ++s) {  // untimed: leave the random start behind
        ff.compute(sys, Tally::ForcesOnly);
        model.prepare(sys, ff, p.rate);
        model.advance(sys, ff, p.dt, p.rate, 0);
    }
    double iterations = 0, refactored = 0, updates = 0;
    for (auto _ : state) {
        ff.compute(sys, Tally::ForcesOnly);
        model.prepare(sys, ff, p.rate);
        model.advance(sys, ff, p.dt, p.rate, 0);
        if constexpr (std::is_same_v<ModelT, Cd0>)
        {
            iterations += model.last_solve().iterations_x + model.last_solve().iterations_y;
            refactored += model.last_solve().refactored ? 1.0 : 0.0;
            updates += model.last_solve().factor_updates;
        }
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
    state.counters["krylov_its_per_solve"] = iterations / (2.0 * static_cast<double>(state.iterations()));
    state.counters["refactor_per_step"] = refactored / static_cast<double>(state.iterations());
    state.counters["rank1_updates_per_step"] = updates / static_cast<double>(state.iterations());
}
static void BM_Rd0Step(benchmark::State& s) { run_model<Rd0>(s); }
static void BM_Cd0Step(benchmark::State& s) { run_model<Cd0>(s); }
static void BM_Cd0EigenStep(benchmark::State& s) { run_model<Cd0>(s, "eigen"); }
BENCHMARK(BM_Rd0Step)->ArgName("N")->Arg(1024)->Arg(4096)->Arg(16384)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Cd0Step)->ArgName("N")->Arg(1024)->Arg(4096)->Arg(16384)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Cd0EigenStep)->ArgName("N")->Arg(1024)->Arg(4096)->Arg(16384)->Arg(65536)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    // Remaining arguments are PETSc options (-cd0_ksp_type, -cd0_pc_type, -cd0_ksp_rtol, ...).
    PetscInitialize(&argc, &argv, nullptr, nullptr);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    PetscFinalize();
    return 0;
}
