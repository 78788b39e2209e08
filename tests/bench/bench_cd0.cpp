// CD0 against RD0 per step (harmonic, Euler, Δt = 0.2, γ̇ = 1e-4) at N = 1024 … 65536 and
// φ = 0.80 (below φ_J), 0.84, 0.86, for each CD0 backend. Every run at a given (N, φ) starts
// from the same sheared state, CD0's own steady flow: the random start sheared by CD0 at
// γ̇ = 1e-4 to strain 0.2 (10⁴ steps, made once per (N, φ) and reused). Contacts change
// per step at a rate that depends on the flow's history: right after the random start's
// quench 2-3x more often than under shear, and in a state sheared by RD0 (this benchmark's
// start before) still 1.4x (N = 16384) to 1.7x (65536) more often at φ = 0.80 after 200
// CD0 steps, relaxing to CD0's own rate over a strain of 0.1-0.2. Each
// CD0 benchmark also times RD0
// steps from the same configuration in the same process right before and after its own timed
// loop (process CPU time, so that other jobs on a shared machine count less), and reports:
//   rd0_us          RD0 CPU time per step (mean of the runs before and after)
//   cd0_us          CD0 CPU time per step
//   cd0_over_rd0    the ratio: a CD0 step in RD0 steps
//   refactor_per_step, rank1_updates_per_step, krylov_its_per_solve   the solver's counters
//   upkeep_us, factor_solve_us   wall-clock µs per step in the updated CHOLMOD factor (petsc
//                   and cholmod backends): keeping it equal to the matrix, and its solves
// JAMSIM_BENCH_CD0_STATES=<directory> keeps the sheared states there between runs (making
// them is most of a run: about 2 minutes per φ at N = 65536, 40 at 262144, where shearing
// from the random start peaked at 10 GB of memory before CD0 relaxed its random start).
// Solver options for the PETSc backend come from the command line through PETSc's options
// database, e.g.  jamsim_bench_cd0 --benchmark_filter=Petsc -cd0_pc_type icc
#include <benchmark/benchmark.h>
#include <petscsys.h>

#include <omp.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

double wall_seconds() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

ReplicaParams bench_params(const benchmark::State& state) {
    ReplicaParams p;
    p.n = state.range(0);
    p.phi = static_cast<double>(state.range(1)) / 100.0;
    p.rate = 1e-4;
    return p;
}

template <class ModelT> void step(ModelT& model, System& sys, ForceField& ff, const ReplicaParams& p) {
    ff.compute(sys, Tally::ForcesOnly);
    model.prepare(sys, ff, p.rate);
    model.advance(sys, ff, p.dt, p.rate, 0);
}

/// CPU seconds per RD0 step from a copy of `start` (enough steps for ~0.2 s).
double rd0_step_seconds(const System& start, const ReplicaParams& p) {
    System sys = start;
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(p);
    for (int s = 0; s < 20; ++s) step(model, sys, ff, p);
    const int steps = std::max(50, static_cast<int>(2e7 / static_cast<double>(p.n) / 4.0));
    const double t0 = cpu_seconds();
    for (int s = 0; s < steps; ++s) step(model, sys, ff, p);
    return (cpu_seconds() - t0) / steps;
}

/// Where the sheared states are kept between runs: the directory named by the environment
/// variable JAMSIM_BENCH_CD0_STATES (made by the caller), or none. Each is a replica
/// checkpoint file (io/checkpoint_file.hpp: written atomically, format checked on reading);
/// a state is the state of this build of the code, so remove the files after a change of CD0
/// or of the start.
std::string state_path(const ReplicaParams& p) {
    const char* dir = std::getenv("JAMSIM_BENCH_CD0_STATES");
    if (!dir || !*dir) return {};
    return std::string(dir) + "/cd0_flow_N" + std::to_string(p.n) + "_phi" + std::to_string(std::lround(p.phi * 100)) +
           ".h5";
}

/// CD0's start (random positions relaxed by relax_cd0_start) sheared by CD0 to strain 0.2 at the benchmark's rate: the same state for
/// every backend at a given (N, φ), made once (or read from JAMSIM_BENCH_CD0_STATES). Made
/// with the cholmod backend, which PETSc options on the command line do not reach (the
/// default gives the same bits).
System sheared_start(const ReplicaParams& p) {
    static std::map<std::pair<long, long>, System> made;
    const std::pair<long, long> key{static_cast<long>(p.n), std::lround(p.phi * 100)};
    if (const auto at = made.find(key); at != made.end()) return at->second;
    const std::string cached = state_path(p);
    if (!cached.empty() && std::filesystem::exists(cached)) {
        System sys = read_state_system(cached);
        if (static_cast<std::int64_t>(sys.particles.size()) != p.n)
            throw std::runtime_error("bench_cd0: " + cached + " is not a state of N = " + std::to_string(p.n));
        return made.emplace(key, std::move(sys)).first->second;
    }
    System sys = start_system(p);  // a CD0 replica's start: random positions, relaxed
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    ReplicaParams flow = p;
    flow.solver = "cholmod";
    flow.petsc_options.clear();
    Cd0 model(flow);
    const auto steps = static_cast<int>(0.2 / (p.rate * p.dt));
    for (int s = 0; s < steps; ++s) step(model, sys, ff, flow);
    if (!cached.empty()) write_checkpoint(cached, p, ReplicaState{.system = sys});
    return made.emplace(key, sys).first->second;
}

void run_cd0(benchmark::State& state, const char* solver, const char* options) {
    ReplicaParams p = bench_params(state);
    p.solver = solver;
    p.petsc_options = options;
    System sys = sheared_start(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    const double rd0_before = rd0_step_seconds(sys, p);
    Cd0 model(p);
    step(model, sys, ff, p);  // the first factorisation is not a step's cost
    double iterations = 0, refactored = 0, updates = 0, upkeep = 0, factor_solve = 0;
    const double t0 = cpu_seconds();
    for (auto _ : state) {
        step(model, sys, ff, p);
        const auto info = model.last_solve();
        iterations += info.iterations_x + info.iterations_y;
        refactored += info.refactored ? 1.0 : 0.0;
        updates += info.factor_updates;
        upkeep += info.factor_upkeep_seconds;
        factor_solve += info.factor_solve_seconds;
    }
    const double cd0 = (cpu_seconds() - t0) / static_cast<double>(state.iterations());
    const double rd0 = 0.5 * (rd0_before + rd0_step_seconds(sys, p));
    const auto steps = static_cast<double>(state.iterations());
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
    state.counters["rd0_us"] = rd0 * 1e6;
    state.counters["cd0_us"] = cd0 * 1e6;
    state.counters["cd0_over_rd0"] = cd0 / rd0;
    state.counters["krylov_its_per_solve"] = iterations / (2.0 * steps);
    state.counters["refactor_per_step"] = refactored / steps;
    state.counters["rank1_updates_per_step"] = updates / steps;
    state.counters["upkeep_us"] = upkeep / steps * 1e6;
    state.counters["factor_solve_us"] = factor_solve / steps * 1e6;
}

/// Wall-clock seconds per RD0 step from a copy of `start` on the current thread count.
double rd0_step_wall_seconds(const System& start, const ReplicaParams& p) {
    System sys = start;
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(p);
    for (int s = 0; s < 20; ++s) step(model, sys, ff, p);
    const int steps = std::max(50, static_cast<int>(2e7 / static_cast<double>(p.n) / 4.0));
    const double t0 = wall_seconds();
    for (int s = 0; s < steps; ++s) step(model, sys, ff, p);
    return (wall_seconds() - t0) / steps;
}

/// CD0 (default backend) on T threads inside the replica, in CD0's own flow at φ = 0.84:
/// wall-clock time per step (threads share the work, so CPU time would count it T times),
/// particle-steps per second, and the same run's RD0 steps on the same thread count before
/// and after (cd0_over_rd0). `factor_us` is the wall-clock time per step in the updated
/// CHOLMOD factor (its upkeep and its solves), `factor_fraction` its share of the step.
void BM_Cd0Threads(benchmark::State& state) {
    const int before = kernel_threads();
    ReplicaParams p = bench_params(state);
    p.phi = 0.84;
    System sys = sheared_start(p);  // made on the caller's thread count (the same bits on any)
    set_kernel_threads(static_cast<int>(state.range(1)));
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    const double rd0_before = rd0_step_wall_seconds(sys, p);
    Cd0 model(p);
    step(model, sys, ff, p);  // the first factorisation is not a step's cost
    double upkeep = 0, factor_solve = 0, updates = 0;
    const double t0 = wall_seconds();
    for (auto _ : state) {
        step(model, sys, ff, p);
        const auto info = model.last_solve();
        upkeep += info.factor_upkeep_seconds;
        factor_solve += info.factor_solve_seconds;
        updates += info.factor_updates;
    }
    const auto steps = static_cast<double>(state.iterations());
    const double cd0 = (wall_seconds() - t0) / steps;
    const double rd0 = 0.5 * (rd0_before + rd0_step_wall_seconds(sys, p));
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
    state.counters["cd0_us"] = cd0 * 1e6;
    state.counters["rd0_us"] = rd0 * 1e6;
    state.counters["cd0_over_rd0"] = cd0 / rd0;
    state.counters["upkeep_us"] = upkeep / steps * 1e6;
    state.counters["factor_solve_us"] = factor_solve / steps * 1e6;
    state.counters["factor_fraction"] = (upkeep + factor_solve) / steps / cd0;
    state.counters["rank1_updates_per_step"] = updates / steps;
    set_kernel_threads(before);
}

/// Steps of BM_Cd0ThreadsInterleaved: several cycles of the factor's life (a fresh analysis,
/// then fill from contacts that form outside its pattern until the next), where BM_Cd0Threads'
/// 500 steps see a fresh factor only (tests/bench/cd0_threads.md, "CD0 over long runs").
constexpr long kLongRun = 4000;

/// CD0 over a long run on one thread and on T, in one process: the steps alternate between
/// one thread and T (the same bits on any count, so the replica runs as it would on either),
/// each count's steps timed apart. Runs on a busy or shared machine swing by tens of percent
/// between processes; alternating step by step exposes both counts to the same load, and both
/// to every stage of the factor's life alike. (A step after a change of count finds its data
/// in the other core's cache, on both sides alike.) Counters: speedup (one thread's time per
/// step over T threads'), cd0_us and cd0_1_us (per step on T threads and on one), cd0_over_rd0
/// on T threads (RD0 timed before and after, on T threads), fresh_factors_per_1000 (steps
/// whose solve factorised afresh: a new ordering and analysis, or a failed downdate) and
/// fresh_us, their time per step (over all steps). The serial part of a step on T threads:
/// serial_us, its wall time outside parallel regions (TimedRegion), of which fresh factors
/// are part; serial_fraction, Amdahl's S / (S + T R) from it (R: the time inside regions,
/// where a thread waiting for another also counts); amdahl_fraction, the f that gives the
/// measured speed-up, (T / speedup − 1) / (T − 1), which counts the waits too.
void BM_Cd0ThreadsInterleaved(benchmark::State& state) {
    const int before = kernel_threads();
    ReplicaParams p = bench_params(state);
    p.phi = 0.84;
    System sys = sheared_start(p);
    const int threads = static_cast<int>(state.range(1));
    set_kernel_threads(threads);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    const double rd0_before = rd0_step_wall_seconds(sys, p);
    Cd0 model(p);
    step(model, sys, ff, p);     // the first factorisation is not a step's cost
    double seconds[2] = {0, 0};  // [0]: one thread, [1]: T threads
    long counted[2] = {0, 0};
    long k = 0, fresh = 0;
    double inside = 0, fresh_seconds = 0;  // T threads: time in parallel regions; all: fresh factors
    for (auto _ : state) {
        const int which = static_cast<int>(k++ % 2);
        set_kernel_threads(which == 0 ? 1 : threads);
        const double in_regions = region_clock().seconds;
        const double t0 = wall_seconds();
        step(model, sys, ff, p);
        seconds[which] += wall_seconds() - t0;
        if (which == 1) inside += region_clock().seconds - in_regions;
        ++counted[which];
        fresh += model.last_solve().refactored ? 1 : 0;
        fresh_seconds += model.last_solve().factor_fresh_seconds;
    }
    set_kernel_threads(threads);
    const double one = seconds[0] / static_cast<double>(counted[0]);
    const double many = seconds[1] / static_cast<double>(counted[1]);
    const double rd0 = 0.5 * (rd0_before + rd0_step_wall_seconds(sys, p));
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
    state.counters["speedup"] = one / many;
    state.counters["cd0_us"] = many * 1e6;
    state.counters["cd0_1_us"] = one * 1e6;
    state.counters["cd0_over_rd0"] = many / rd0;
    state.counters["fresh_factors_per_1000"] = 1000.0 * static_cast<double>(fresh) / static_cast<double>(k);
    state.counters["fresh_us"] = 1e6 * fresh_seconds / static_cast<double>(k);
    const double serial = seconds[1] - inside, team = static_cast<double>(threads);
    state.counters["serial_us"] = 1e6 * serial / static_cast<double>(counted[1]);
    state.counters["serial_fraction"] = serial / (serial + team * inside);
    state.counters["amdahl_fraction"] = (team * many / one - 1.0) / (team - 1.0);
    set_kernel_threads(before);
}

void BM_Rd0Step(benchmark::State& state) {
    const ReplicaParams p = bench_params(state);
    System sys = sheared_start(p);
    ForceField ff(potential::make_soft_sphere(2.0), p.skin);
    Rd0 model(p);
    for (int s = 0; s < 200; ++s) step(model, sys, ff, p);
    for (auto _ : state) step(model, sys, ff, p);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * p.n);
}
/// The memory bandwidth a pass over L could have: a streaming read (sum) of 512 MiB on T
/// threads (bytes_per_second). The factor's passes read L (22 MB at N = 65536) at about a
/// third to a half of this on one thread (tests/bench/cd0_threads.md).
void BM_ReadBandwidth(benchmark::State& state) {
    using Four = double __attribute__((vector_size(32)));
    const std::size_t n = std::size_t{64} << 20;  // doubles
    static std::vector<double> data(n, 1.0);
    const int threads = static_cast<int>(state.range(0));
    double total = 0;
    for (auto _ : state) {
        double sum = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sum)
        {
            const std::size_t team = static_cast<std::size_t>(omp_get_num_threads());
            const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
            const std::size_t from = n * t / team / 16 * 16, to = t + 1 == team ? n : n * (t + 1) / team / 16 * 16;
            Four s0{}, s1{}, s2{}, s3{};
            for (std::size_t i = from; i < to; i += 16) {
                Four a, b, c, d;
                std::memcpy(&a, &data[i], sizeof a);
                std::memcpy(&b, &data[i + 4], sizeof b);
                std::memcpy(&c, &data[i + 8], sizeof c);
                std::memcpy(&d, &data[i + 12], sizeof d);
                s0 += a;
                s1 += b;
                s2 += c;
                s3 += d;
            }
            const Four s = (s0 + s1) + (s2 + s3);
            sum += (s[0] + s[1]) + (s[2] + s[3]);
        }
        total += sum;
    }
    benchmark::DoNotOptimize(total);
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                            static_cast<std::int64_t>(n * sizeof(double)));
}
}  // namespace

int main(int argc, char** argv) {
    // Fixed step counts (after the preparation): enough steps to span
    // several neighbour-list rebuilds, so that the factorisations at rebuilds are averaged in.
    auto steps = [](long n) { return n <= 1024 ? 3000L : n <= 4096 ? 1500L : n <= 65536 ? 500L : 100L; };
    const struct {
        const char* name;
        const char* solver;
        const char* options;  // PETSc options of this option set
        long largest;
    } backends[] = {
        {"Cd0Petsc", "petsc", "", 262144},  // the default: KSP + the updated CHOLMOD factor
        {"Cd0Cholmod", "cholmod", "", 262144},
        {"Cd0Eigen", "eigen", "", 65536},
        {"Cd0CholmodAmd", "cholmod-amd", "", 65536},
        // PETSc's own preconditioners (CG, kept while <= 2 iterations):
        {"Cd0PetscCholeskyCholmod", "petsc", "-cd0_pc_type cholesky -cd0_pc_factor_mat_solver_type cholmod", 4096},
        {"Cd0PetscCholeskyMumps", "petsc", "-cd0_pc_type cholesky -cd0_pc_factor_mat_solver_type mumps", 4096},
        {"Cd0PetscHypre", "petsc", "-cd0_pc_type hypre", 4096},
    };
    for (long n = 1024; n <= 262144; n *= 4)
        for (long phi : {80L, 84L, 86L}) {
            if (n > 65536 && phi != 84) continue;
            if (n <= 65536)
                benchmark::RegisterBenchmark("BM_Rd0Step", BM_Rd0Step)
                    ->ArgNames({"N", "phi100"})
                    ->Args({n, phi})
                    ->Iterations(steps(n))
                    ->Unit(benchmark::kMicrosecond);
            for (const auto& b : backends) {
                if (n > b.largest) continue;
                const char *solver = b.solver, *options = b.options;
                benchmark::RegisterBenchmark((std::string("BM_") + b.name).c_str(),
                                             [solver, options](benchmark::State& st) { run_cd0(st, solver, options); })
                    ->ArgNames({"N", "phi100"})
                    ->Args({n, phi})
                    ->Iterations(steps(n))
                    ->Unit(benchmark::kMicrosecond);
            }
        }
    // CD0 on threads (φ = 0.84; here: --benchmark_filter='BM_Cd0Threads.*threads:(1|2)$').
    for (long n : {16384L, 65536L})
        for (long t : {1L, 2L, 4L, 8L, 16L})
            benchmark::RegisterBenchmark("BM_Cd0Threads", BM_Cd0Threads)
                ->ArgNames({"N", "threads"})
                ->Args({n, t})
                ->Iterations(steps(n))
                ->UseRealTime()
                ->Unit(benchmark::kMicrosecond);
    for (long n : {16384L, 65536L})
        for (long t : {2L, 4L, 8L, 16L})
            benchmark::RegisterBenchmark("BM_Cd0ThreadsInterleaved", BM_Cd0ThreadsInterleaved)
                ->ArgNames({"N", "threads"})
                ->Args({n, t})
                ->Iterations(kLongRun)
                ->UseRealTime()
                ->Unit(benchmark::kMicrosecond);
    for (long t : {1L, 2L, 4L, 8L, 16L})
        benchmark::RegisterBenchmark("BM_ReadBandwidth", BM_ReadBandwidth)
            ->ArgNames({"threads"})
            ->Arg(t)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    // Remaining arguments are PETSc options (-cd0_ksp_type, -cd0_pc_type, -cd0_ksp_rtol, ...).
    PetscInitialize(&argc, &argv, nullptr, nullptr);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    PetscFinalize();
    return 0;
}
