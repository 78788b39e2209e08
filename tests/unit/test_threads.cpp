// Threads inside a replica: the force loop, the neighbour list and a whole replica give the
// same bits on 1, 2, 3 and 4 threads (more threads than cores is fine here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/observe/velocity_correlation.hpp"
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
Evaluation evaluate(const System& sys, const potential::SoftSphere& pot, int threads, Tally tally, bool record,
                    bool offsets) {
    const ThreadCount count(threads);
    NeighborList list(0.3);
    const Particles& p = sys.particles;
    list.build(p.x, p.y, p.diameter, sys.box);
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
    const System sys = testing::random_configuration(20000, 0.86, 0.31, 5);
    for (const potential::SoftSphere pot :
         {potential::SoftSphere{potential::Harmonic{}}, potential::SoftSphere{potential::Hertzian{}}})
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

TEST(Threads, ForceBlocksCoverEveryEntryOnce) {
    // The decomposition the force loop shares among threads: several blocks at this size;
    // each entry's neighbour share goes to the neighbour itself when it lies in the owner's
    // block, else to the block's next halo slot, which names that neighbour; sorted by cell,
    // a few per cent of the entries need a slot.
    System sys = testing::random_configuration(20000, 0.86, 0.31, 5);
    Particles& p = sys.particles;
    p.permute(spatial_order(p, sys.box, max_diameter(p) + 0.3));
    NeighborList list(0.3);
    list.build(p.x, p.y, p.diameter, sys.box);
    const ForceBlocks& blocks = list.blocks();
    ASSERT_EQ(blocks.size, ForceBlocks::block_size(p.size()));
    ASSERT_GE(blocks.count, 4u);
    // Walk each block's entries as the force loop does, numbering its halo slots in list
    // order; every slot names its neighbour and sits in its (source, target) group once.
    std::vector<int> grouped(blocks.halo_slots(), 0);
    for (std::size_t b = 0; b < blocks.count; ++b)
        for (std::size_t c = 0; c < blocks.count; ++c)
            for (auto q = blocks.by_target_first[b * blocks.count + c];
                 q < blocks.by_target_first[b * blocks.count + c + 1]; ++q) {
                const auto slot = static_cast<std::size_t>(blocks.by_target[static_cast<std::size_t>(q)]);
                EXPECT_GE(slot, static_cast<std::size_t>(blocks.slot_first[b]));
                EXPECT_LT(slot, static_cast<std::size_t>(blocks.slot_first[b + 1]));
                EXPECT_EQ(blocks.block_of(blocks.halo_disk[slot]), c);
                ++grouped[slot];
            }
    EXPECT_EQ(static_cast<std::size_t>(std::count(grouped.begin(), grouped.end(), 1)), grouped.size());
    for (std::size_t b = 0; b < blocks.count; ++b) {
        auto slot = static_cast<std::size_t>(blocks.slot_first[b]);
        for (auto k = static_cast<std::size_t>(blocks.entry_first[b]);
             k < static_cast<std::size_t>(blocks.entry_first[b + 1]); ++k) {
            ASSERT_EQ(blocks.block_of(list.owner()[k]), b);
            const std::int32_t j = list.neighbor()[k];
            if (blocks.block_of(j) == b) continue;
            EXPECT_EQ(blocks.halo_disk[slot], j);
            ++slot;
        }
        EXPECT_EQ(slot, static_cast<std::size_t>(blocks.slot_first[b + 1]));
    }
    EXPECT_LT(static_cast<double>(blocks.halo_slots()), 0.1 * static_cast<double>(list.size()));
}

TEST(Threads, OneBlockIsThePlainScatterLoop) {
    // Up to 4096 disks the loop is the one-pass scatter in list order: the same bits as a
    // direct sum f_i += f_ij, f_j −= f_ij over the entries.
    const System sys = testing::random_configuration(3000, 0.86, 0.31, 7);
    const Particles& p = sys.particles;
    NeighborList list(0.3);
    list.build(p.x, p.y, p.diameter, sys.box);
    ASSERT_EQ(list.blocks().count, 1u);
    const potential::SoftSphere pot{potential::Harmonic{}};
    const Evaluation e = evaluate(sys, pot, 1, Tally::Full, false, false);
    std::vector<double> fx(p.size(), 0.0), fy(p.size(), 0.0);
    for_each_pair(list, sys.box, p.x, p.y, [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool) {
        const double fr = potential::Harmonic{}(norm2(r), list.contact()[k]).force_over_r;
        fx[i] += fr * r.x;
        fy[i] += fr * r.y;
        fx[j] -= fr * r.x;
        fy[j] -= fr * r.y;
    });
    EXPECT_TRUE(same_bits(fx, e.fx));
    EXPECT_TRUE(same_bits(fy, e.fy));
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
        EXPECT_TRUE(
            std::equal(one.neighbor().begin(), one.neighbor().end(), many.neighbor().begin(), many.neighbor().end()));
        EXPECT_TRUE(std::equal(one.owner().begin(), one.owner().end(), many.owner().begin(), many.owner().end()));
        EXPECT_TRUE(same_bits(std::vector<double>(one.shift_x().begin(), one.shift_x().end()),
                              std::vector<double>(many.shift_x().begin(), many.shift_x().end())));
        EXPECT_TRUE(same_bits(std::vector<double>(one.shift_y().begin(), one.shift_y().end()),
                              std::vector<double>(many.shift_y().begin(), many.shift_y().end())));
    }
}

/// A sheared replica of `model` at φ = 0.84, γ̇ = 1e-3 (the tests below).
ReplicaParams sheared(const std::string& model, std::int64_t n, double strain, double sample_interval,
                      const std::string& integrator) {
    ReplicaParams p;
    p.model = model;
    p.n = n;
    p.phi = 0.84;
    p.rate = 1e-3;
    p.strain = strain;
    p.sample_interval = sample_interval;
    p.integrator = integrator;
    return p;
}

TEST(Threads, Rd0ReplicaIsTheSameOnAnyThreadCount) {
    // 10000 disks: three blocks of the force loop and of the sums over disks.
    const ReplicaParams p = sheared("RD0", 10000, 0.02, 0.005, "heun");
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

TEST(Threads, VelocityCorrelationIsTheSameOnAnyThreadCount) {
    // g_y over three blocks of disks by height (parallel sort and per-block bins).
    System sys = testing::random_configuration(10000, 0.84, 0.2, 11);
    Particles& p = sys.particles;
    for (std::size_t i = 0; i < p.size(); ++i) p.uy[i] = std::sin(0.7 * static_cast<double>(i));
    auto sums = [&](int threads) {
        const ThreadCount count(threads);
        VelocityCorrelation g(sys.box.side());
        g.accumulate(sys);
        g.accumulate(sys);
        return g.sums();
    };
    const VelocityCorrelation::Sums one = sums(1);
    EXPECT_GT(one.count[0], 0.0);
    for (const int t : thread_counts()) {
        const VelocityCorrelation::Sums many = sums(t);
        EXPECT_TRUE(same_bits(one.sum, many.sum)) << t << " threads";
        EXPECT_EQ(one.count, many.count);
        EXPECT_TRUE(same_bits(one.uy2_sum, many.uy2_sum));
    }
}

/// A CD0 replica from random positions (contacts form and break by the thousand in its first
/// steps: fresh factors, in-place updates of the factor and its solves all run) through the
/// `solver` backend, on `threads` threads.
ReplicaResult cd0_replica(const std::string& solver, const std::string& integrator, int threads) {
    ReplicaParams p = sheared("CD0", 8192, 0.008, 0.002, integrator);
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

}  // namespace
}  // namespace jamsim
