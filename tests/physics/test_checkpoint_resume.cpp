// Checkpoints inside a replica: a run continued from any saved state (in memory, or through a
// checkpoint file) is bitwise the run that was never interrupted, for every model and
// protocol with checkpoint steps; saving changes nothing; a stop request ends the run at the
// next checkpoint step with its state saved.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "jamsim/io/checkpoint_file.hpp"
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
    const CheckpointPolicy keep_all{.due = [] { return true; },
                                    .save = [&](const ReplicaState& s) { saved.push_back(s); },
                                    .stop = {}};
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
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("jamsim_ckpt_" + p.model + ".h5")).string();
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
    EXPECT_EQ(at_stop[0].step, 3 * p.checkpoint_steps) << p.model;
    expect_same(plain, run_replica(p, {.resume = &at_stop[0]}), p.model + " after a stop");
}

} // namespace

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
    p.sample_interval = 5e-3;
    p.checkpoint_steps = 10;
    check_resume(p);
}

// A checkpoint of another replica, or a damaged one, is refused with a message naming it.
TEST(CheckpointResume, ForeignCheckpointRefused) {
    const ReplicaParams p = replica("RD0");
    std::vector<ReplicaState> saved;
    const CheckpointPolicy keep{.due = [] { return true; },
                                .save = [&](const ReplicaState& s) { saved.push_back(s); }, .stop = {}};
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
