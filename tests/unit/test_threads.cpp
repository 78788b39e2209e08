// Threads inside a replica: the force loop, the neighbour list and a whole replica give the
// same bits on 1, 2, 3 and 4 threads (more threads than cores is fine here).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/run/replica.hpp"
#include "support/configurations.hpp"

namespace jamsim {
namespace {

/// The thread counts compared with one thread: 2, 3 and 4, and up to JAMSIM_TEST_MAX_THREADS
/// (8, 16, ...) where that is set (a machine with many cores).
std::vector<int> thread_counts() {
    std::vector<int> out{2, 3, 4};
    if (const char* most = std::getenv("JAMSIM_TEST_MAX_THREADS"))
        for (int t = 8; t <= std::atoi(most); t *= 2) out.push_back(t);
    return out;
}

/// Restores the kernel's thread count when a test ends.
struct ThreadCount {
    explicit ThreadCount(int t) : before(kernel_threads()) { set_kernel_threads(t); }
    ~ThreadCount() { set_kernel_threads(before); }
    int before;
};

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Evaluation {
    std::vector<double> fx, fy, sum_ry;
    std::vector<std::uint8_t> touching;
    ForceResult result;
};

/// Forces of `sys` on `threads` threads, through a fresh list (built on those threads too).
Evaluation evaluate(const System& sys, const potential::SoftSphere& pot, int threads, Tally tally,
                    bool record, bool offsets) {
    const ThreadCount count(threads);
    NeighborList list(0.3);
    const Particles& p = sys.particles;
    list.build(p.x, p.y, p.diameter, sys.box);
    list.ensure_incidence();
    Evaluation e;
    e.fx.resize(p.size());
    e.fy.resize(p.size());
    e.sum_ry.resize(p.size());
    e.touching.resize(list.size());
    PairScratch scratch;
    if (offsets) {  // positions split as base + small offsets (the minimisers' form)
        std::vector<double> ox(p.size()), oy(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            ox[i] = 1e-3 * std::sin(static_cast<double>(i));
            oy[i] = 1e-3 * std::cos(static_cast<double>(i));
        }
        e.result = compute_pair_forces_split(pot, list, sys.box, p.x, p.y, ox, oy, e.fx, e.fy, scratch, tally);
    } else {
        const ContactRecord rec = record ? ContactRecord{e.touching.data(), e.sum_ry.data()} : ContactRecord{};
        e.result = compute_pair_forces(pot, list, sys.box, p.x, p.y, e.fx, e.fy, scratch, tally, rec);
    }
    return e;
}

TEST(Threads, ForceLoopGivesTheSameBitsOnAnyThreadCount) {
    const System sys = testing::random_configuration(6000, 0.86, 0.31, 5);
    for (const potential::SoftSphere pot : {potential::SoftSphere{potential::Harmonic{}},
                                            potential::SoftSphere{potential::Hertzian{}}})
        for (const Tally tally : {Tally::ForcesOnly, Tally::Full})
            for (const bool record : {false, true})
                for (const bool offsets : {false, true}) {
                    if (record && offsets) continue;
                    const Evaluation one = evaluate(sys, pot, 1, tally, record, offsets);
                    for (const int t : thread_counts()) {
                        const Evaluation many = evaluate(sys, pot, t, tally, record, offsets);
                        SCOPED_TRACE("threads " + std::to_string(t) + " full " + std::to_string(tally == Tally::Full) +
                                     " record " + std::to_string(record) + " offsets " + std::to_string(offsets));
                        EXPECT_TRUE(same_bits(one.fx, many.fx));
                        EXPECT_TRUE(same_bits(one.fy, many.fy));
                        EXPECT_TRUE(same_bits(one.result.energy, many.result.energy));
                        EXPECT_TRUE(same_bits(one.result.virial_xx, many.result.virial_xx));
                        EXPECT_TRUE(same_bits(one.result.virial_xy, many.result.virial_xy));
                        EXPECT_TRUE(same_bits(one.result.virial_yy, many.result.virial_yy));
                        EXPECT_EQ(one.result.contacts, many.result.contacts);
                        if (record) {
                            EXPECT_TRUE(same_bits(one.sum_ry, many.sum_ry));
                            EXPECT_EQ(one.touching, many.touching);
                        }
                    }
                }
}

TEST(Threads, ForceLoopOnThreadsIsNotTheSerialLoopByAccident) {
    // The threaded path must really run: with 2 threads a list of this size takes it.
    const System sys = testing::random_configuration(6000, 0.86, 0.31, 5);
    const ThreadCount count(2);
    NeighborList list(0.3);
    list.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    EXPECT_GE(list.size(), kThreadedLoopMin);
    list.ensure_incidence();
    EXPECT_TRUE(list.has_incidence());
    // Every entry appears twice: once for its owner, once for its neighbour.
    EXPECT_EQ(list.incidence().size(), 2 * list.size());
}

TEST(Threads, NeighbourListIsTheSameOnAnyThreadCount) {
    const System sys = testing::random_configuration(6000, 0.84, -0.42, 9);
    const Particles& p = sys.particles;
    NeighborList one(0.3);
    {
        const ThreadCount count(1);
        one.build(p.x, p.y, p.diameter, sys.box);
    }
    for (const int t : thread_counts()) {
        const ThreadCount count(t);
        NeighborList many(0.3);
        many.build(p.x, p.y, p.diameter, sys.box);
        EXPECT_TRUE(std::equal(one.first().begin(), one.first().end(), many.first().begin(), many.first().end()));
        EXPECT_TRUE(std::equal(one.neighbor().begin(), one.neighbor().end(), many.neighbor().begin(),
                               many.neighbor().end()));
        EXPECT_TRUE(std::equal(one.owner().begin(), one.owner().end(), many.owner().begin(), many.owner().end()));
        EXPECT_TRUE(same_bits(std::vector<double>(one.shift_x().begin(), one.shift_x().end()),
                              std::vector<double>(many.shift_x().begin(), many.shift_x().end())));
        EXPECT_TRUE(same_bits(std::vector<double>(one.shift_y().begin(), one.shift_y().end()),
                              std::vector<double>(many.shift_y().begin(), many.shift_y().end())));
    }
}

TEST(Threads, Rd0ReplicaIsTheSameOnAnyThreadCount) {
    ReplicaParams p;
    p.model = "RD0";
    p.n = 4096;
    p.phi = 0.84;
    p.rate = 1e-3;
    p.strain = 0.05;
    p.sample_interval = 0.01;
    p.integrator = "heun";
    const ReplicaResult one = [&] {
        const ThreadCount count(1);
        return run_replica(p);
    }();
    for (const int t : thread_counts()) {
        const ThreadCount count(t);
        const ReplicaResult many = run_replica(p);
        SCOPED_TRACE("threads " + std::to_string(t));
        for (const auto& c : kSampleColumns)
            EXPECT_TRUE(same_bits(one.series.column(c.member), many.series.column(c.member))) << c.name;
        EXPECT_TRUE(same_bits(one.final_state.particles.x, many.final_state.particles.x));
        EXPECT_TRUE(same_bits(one.final_state.particles.y, many.final_state.particles.y));
        EXPECT_TRUE(same_bits(one.correlation_g, many.correlation_g));
        EXPECT_EQ(one.force_evaluations, many.force_evaluations);
        EXPECT_EQ(one.list_builds, many.list_builds);
    }
}

/// A CD0 replica from random positions (contacts form and break by the thousand in its first
/// steps: fresh factors, in-place updates of the factor and its solves all run) through the
/// `solver` backend, on `threads` threads.
ReplicaResult cd0_replica(const std::string& solver, const std::string& integrator, int threads) {
    ReplicaParams p;
    p.model = "CD0";
    p.n = 8192;
    p.phi = 0.84;
    p.rate = 1e-3;
    p.strain = 0.008;
    p.sample_interval = 0.002;
    p.integrator = integrator;
    p.solver = solver;
    const ThreadCount count(threads);
    return run_replica(p);
}

TEST(Threads, Cd0ReplicaIsTheSameOnAnyThreadCount) {
    for (const std::string solver : {"auto", "cholmod"})
        for (const std::string integrator : {"euler", "heun"}) {
            if (solver == "cholmod" && integrator == "heun") continue;
            const ReplicaResult one = cd0_replica(solver, integrator, 1);
            for (const int t : thread_counts()) {
                const ReplicaResult many = cd0_replica(solver, integrator, t);
                SCOPED_TRACE("CD0 " + solver + " " + integrator + " threads " + std::to_string(t));
                for (const auto& c : kSampleColumns)
                    EXPECT_TRUE(same_bits(one.series.column(c.member), many.series.column(c.member))) << c.name;
                EXPECT_TRUE(same_bits(one.final_state.particles.x, many.final_state.particles.x));
                EXPECT_TRUE(same_bits(one.final_state.particles.y, many.final_state.particles.y));
                EXPECT_TRUE(same_bits(one.final_state.particles.ux, many.final_state.particles.ux));
                EXPECT_TRUE(same_bits(one.final_state.particles.uy, many.final_state.particles.uy));
                EXPECT_EQ(one.list_builds, many.list_builds);
            }
        }
}

} // namespace
} // namespace jamsim
