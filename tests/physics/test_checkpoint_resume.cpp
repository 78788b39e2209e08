// Checkpoints inside a replica: a run continued from any saved state (in memory, or through a
// checkpoint file) is bitwise the run that was never interrupted, for every model and
// protocol with checkpoint steps; saving changes nothing; a stop request ends the run at the
// next checkpoint step with its state saved.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

ReplicaParams replica(const std::string& model) {
    ReplicaParams p;
    p.model = model;
    p.n = 64;
    p.phi = 0.86;
    p.rate = 1e-2;
    p.dt = 0.1;
    p.strain = 0.6;  // 600 steps
    p.transient = 0.2;
    p.sample_interval = 0.02;
    p.checkpoint_steps = 70;
    p.seed = 4;
    return p;
}

/// Bitwise equality of everything a replica writes (NaN equal to NaN).
void expect_same(const ReplicaResult& a, const ReplicaResult& b, const std::string& what) {
    const auto same = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
    ASSERT_EQ(a.series.size(), b.series.size()) << what;
    for (const auto& c : kSampleColumns) {
        const auto x = a.series.column(c.member), y = b.series.column(c.member);
        for (std::size_t k = 0; k < x.size(); ++k)
            ASSERT_TRUE(same(x[k], y[k])) << what << ": " << c.name << " row " << k;
    }
    const FinalConfiguration fa = final_configuration(a.final_state), fb = final_configuration(b.final_state);
    EXPECT_EQ(fa.x, fb.x) << what;
    EXPECT_EQ(fa.y, fb.y) << what;
    EXPECT_EQ(fa.box_strain, fb.box_strain) << what;
    ASSERT_EQ(a.correlation_g.size(), b.correlation_g.size()) << what;
    for (std::size_t k = 0; k < a.correlation_g.size(); ++k)
        EXPECT_TRUE(same(a.correlation_g[k], b.correlation_g[k])) << what << ": g_y bin " << k;
    EXPECT_EQ(a.force_evaluations, b.force_evaluations) << what;
}

void check_resume(const ReplicaParams& p) {
    std::vector<ReplicaState> saved;
    const CheckpointPolicy keep_all{
        .due = [] { return true; }, .save = [&](const ReplicaState& s) { saved.push_back(s); }, .stop = {}};
    const ReplicaResult plain = run_replica(p);
    const ReplicaResult checkpointed = run_replica(p, {.checkpoints = &keep_all});
    expect_same(plain, checkpointed, p.model + ": saving changed the run");
    ASSERT_GE(saved.size(), 3u) << p.model;
    // Continue from the first, a middle and the last saved state.
    for (std::size_t k : {std::size_t{0}, saved.size() / 2, saved.size() - 1}) {
        const ReplicaResult resumed = run_replica(p, {.resume = &saved[k]});
        expect_same(plain, resumed, p.model + " from step " + std::to_string(saved[k].step));
    }
    // Through a checkpoint file.
    const std::string path = (std::filesystem::temp_directory_path() / ("jamsim_ckpt_" + p.model + ".h5")).string();
    write_checkpoint(path, p, saved[saved.size() / 2]);
    const ReplicaState read = read_checkpoint(path, p);
    std::filesystem::remove(path);
    expect_same(plain, run_replica(p, {.resume = &read}), p.model + " from a file");
    // A stop request: the run ends at the next checkpoint step with its state saved there.
    std::vector<ReplicaState> at_stop;
    int asked = 0;
    const CheckpointPolicy stop_at_third{.due = [] { return false; },
                                         .save = [&](const ReplicaState& s) { at_stop.push_back(s); },
                                         .stop = [&] { return ++asked == 3; }};
    EXPECT_THROW(run_replica(p, {.checkpoints = &stop_at_third}), ReplicaInterrupted) << p.model;
    ASSERT_EQ(at_stop.size(), 1u) << p.model;
    EXPECT_EQ(at_stop[0].step, saved[2].step) << p.model;
    expect_same(plain, run_replica(p, {.resume = &at_stop[0]}), p.model + " after a stop");
}

}  // namespace

TEST(CheckpointResume, Rd0EulerAndHeun) {
    ReplicaParams p = replica("RD0");
    check_resume(p);
    p.integrator = "heun";
    check_resume(p);
}

TEST(CheckpointResume, Cd0EigenAndPetsc) {
    ReplicaParams p = replica("CD0");
    p.solver = "eigen";
    p.integrator = "heun";
    check_resume(p);
    p.solver = "petsc";
    p.integrator = "euler";
    check_resume(p);
}

TEST(CheckpointResume, Cd0Cholmod) {  // the default backend: euler and heun
    ReplicaParams p = replica("CD0");
    p.solver = "cholmod";
    check_resume(p);
    p.integrator = "heun";
    check_resume(p);
}

TEST(CheckpointResume, MassiveModels) {
    for (const char* model : {"RD", "CD", "CDn", "CDt"}) check_resume(replica(model));
}

TEST(CheckpointResume, ThermalRd0) {
    ReplicaParams p = replica("RD0T");
    p.temperature = 1e-4;
    check_resume(p);
}

TEST(CheckpointResume, QuasistaticShear) {
    ReplicaParams p = replica("QS");
    p.strain_step = 1e-3;
    p.strain = 0.06;
    p.transient = 0.02;  // within the run (a transient at or beyond the strain is refused)
    p.sample_interval = 5e-3;
    p.checkpoint_steps = 10;
    check_resume(p);
}

// The minimisation protocols: a cooling or quasistatic-shear stage with checkpoint steps
// every checkpoint_steps, then a φ_J search with one before every minimisation; resumed in
// either stage (first, middle and last saved state), and after a stop.
ReplicaParams protocol(const std::string& model) {
    ReplicaParams p = replica(model);
    p.n = 32;
    p.phi = 0.83;
    p.phi_tol = 1e-4;
    p.temperature = 1e-3;
    p.cooling_time = 30;
    p.dt = 0.1;  // 300 cooling steps
    p.strain = 0.05;
    p.strain_step = 1e-3;  // 50 strain steps
    p.checkpoint_steps = 40;
    return p;
}

TEST(CheckpointResume, PhiJSearch) { check_resume(protocol("COMPRESS")); }
TEST(CheckpointResume, Cooling) { check_resume(protocol("COOL")); }
TEST(CheckpointResume, CoolingThenPhiJSearch) {
    const ReplicaParams p = protocol("COOL_COMPRESS");
    std::vector<ReplicaState> saved;
    const CheckpointPolicy keep{
        .due = [] { return true; }, .save = [&](const ReplicaState& s) { saved.push_back(s); }, .stop = {}};
    run_replica(p, {.checkpoints = &keep});
    // Both stages are checkpointed: cooling steps 40, 80, ..., 280, then the search's.
    ASSERT_GT(saved.size(), 8u);
    EXPECT_EQ(saved[6].step, 280);
    EXPECT_TRUE(saved[6].protocol.empty());
    EXPECT_EQ(saved[7].step, 301);
    EXPECT_EQ(saved[7].protocol.size(), 7u);
    check_resume(p);
}
TEST(CheckpointResume, ShearedThenPhiJSearch) { check_resume(protocol("SHEARED")); }

// A checkpoint of another replica, or a damaged one, is refused with a message naming it.
TEST(CheckpointResume, ForeignCheckpointRefused) {
    const ReplicaParams p = replica("RD0");
    std::vector<ReplicaState> saved;
    const CheckpointPolicy keep{
        .due = [] { return true; }, .save = [&](const ReplicaState& s) { saved.push_back(s); }, .stop = {}};
    run_replica(p, {.checkpoints = &keep});
    const std::string path = (std::filesystem::temp_directory_path() / "jamsim_ckpt_foreign.h5").string();
    write_checkpoint(path, p, saved.front());
    ReplicaParams other = p;
    other.phi = 0.85;
    try {
        read_checkpoint(path, other);
        ADD_FAILURE() << "a checkpoint of phi = 0.86 was accepted for phi = 0.85";
    } catch (const CheckpointError& e) {
        EXPECT_NE(std::string(e.what()).find("belongs to another replica"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    std::filesystem::resize_file(path, 100);  // a file cut short
    EXPECT_THROW(read_checkpoint(path, p), CheckpointError);
    std::filesystem::remove(path);
}

// A long minimisation calls the run's hook between iterations (a campaign's farm answers its
// ranks there: rank 0 used to leave them waiting for a whole RAND quench), about once every
// kIterationsBetweenCalls iterations, and the result is the run without the hook, bitwise.
TEST(CheckpointResume, MinimisationCallsTheHookBetweenIterations) {
    ReplicaParams p = replica("RAND");
    p.n = 256;
    const ReplicaResult plain = run_replica(p);
    int calls = 0;
    const ReplicaResult hooked = run_replica(p, {.after_sample = [&](double) { ++calls; }});
    expect_same(plain, hooked, "RAND with the hook");
    // One call for the recorded state, the rest from inside the quench; it takes at least one
    // force evaluation per iteration.
    const std::int64_t evaluations = plain.force_evaluations;
    ASSERT_GT(evaluations, 4 * MinimizeCriteria::kIterationsBetweenCalls) << "a quench too short to tell";
    EXPECT_GE(calls, 2);
    EXPECT_LE(calls, 1 + evaluations / MinimizeCriteria::kIterationsBetweenCalls);
}
