// The time left to a campaign from its finished replicas (campaign/throughput.hpp), against
// answers worked out by hand.
#include <gtest/gtest.h>

#include <vector>

#include "jamsim/campaign/throughput.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {
namespace {

ReplicaParams replica(std::int64_t n, double phi, double strain) {
    ReplicaParams p;
    p.model = "RD0";
    p.n = n;
    p.phi = phi;
    p.rate = 1e-3;
    p.strain = strain;
    p.sample_interval = strain / 10;
    return p;
}

using S = ReplicaStatus;

// Two groups that run at different speeds per unit of estimated cost: N = 64 at 1 s per
// unit of 1e6 evaluations, N = 4096 at 5 s. The time left is each unfinished replica's cost
// at its own group's rate; one rate over every finished replica (the estimate before) gave
// the large ones' time at the small ones' speed, a fraction of it.
TEST(Throughput, EachGroupAtItsOwnRate) {
    CampaignSpec spec;
    spec.replicas = {replica(64, 0.84, 10.0), replica(64, 0.84, 10.0), replica(4096, 0.84, 0.05),
                     replica(4096, 0.84, 0.05), replica(4096, 0.84, 0.05)};
    const double small = estimated_cost(spec.replicas[0]), large = estimated_cost(spec.replicas[2]);
    const std::vector<S> status = {S::Done, S::Done, S::Done, S::Running, S::Pending};
    const std::vector<double> wall = {small * 1e-6, small * 1e-6, large * 5e-6, 0, 0};
    const std::vector<double> progress = {1, 1, 1, 0.25, 0};
    const TimeLeft left = time_left(spec, status, wall, progress);
    EXPECT_TRUE(left.measured);
    EXPECT_NEAR(left.core_seconds, large * 5e-6 * 1.75, 1e-9 * left.core_seconds);
    // No ladder: the longest chain is the largest replica left, the pending one.
    EXPECT_NEAR(left.longest_chain, large * 5e-6, 1e-9 * left.longest_chain);
    EXPECT_NEAR(left.on(1), large * 5e-6 * 1.75, 1e-9 * left.core_seconds);
    EXPECT_NEAR(left.on(8), large * 5e-6, 1e-9 * left.core_seconds);  // the chain bounds it
    const double one_rate = (2 * small * 1e-6 + large * 5e-6) / (2 * small + large);
    EXPECT_GT(left.core_seconds, 2 * one_rate * large * 1.75);  // 3.2 times
}

// A group not measured takes its (model, N) at another phi, else its model at another N.
TEST(Throughput, UnmeasuredGroupsFallBack) {
    Throughput rate;
    const ReplicaParams a = replica(64, 0.80, 1.0), b = replica(64, 0.86, 1.0), c = replica(256, 0.80, 1.0);
    EXPECT_FALSE(rate.measured());
    EXPECT_DOUBLE_EQ(rate.seconds_per_cost(a), 1.0 / kNominalEvaluationsPerSecond);
    rate.add(a, estimated_cost(a) * 2e-6);
    EXPECT_DOUBLE_EQ(rate.seconds_per_cost(b), 2e-6);  // same N, other phi
    rate.add(b, estimated_cost(b) * 4e-6);
    EXPECT_DOUBLE_EQ(rate.seconds_per_cost(a), 2e-6);                         // its own group
    EXPECT_NEAR(rate.seconds_per_cost(replica(64, 0.83, 1.0)), 3e-6, 1e-18);  // N = 64's mean
    EXPECT_NEAR(rate.seconds_per_cost(c), 3e-6, 1e-18);                       // the model's
    rate.add(c, 0.0);                                                         // no wall time recorded: not counted
    EXPECT_NEAR(rate.seconds_per_cost(c), 3e-6, 1e-18);
}

// A rate ladder runs its replicas in order: the time left is never below its chain's.
TEST(Throughput, LongestChainBoundsTheTimeLeft) {
    CampaignSpec spec;
    spec.replicas = {replica(64, 0.84, 1.0), replica(64, 0.84, 1.0), replica(64, 0.84, 1.0), replica(64, 0.84, 1.0)};
    spec.predecessor = {-1, 0, 1, -1};  // 0 -> 1 -> 2, and 3 alone
    const double cost = estimated_cost(spec.replicas[0]);
    const TimeLeft left =
        time_left(spec, {S::Done, S::Pending, S::Pending, S::Done}, {cost * 1e-6, 0, 0, cost * 1e-6}, {1, 0, 0, 1});
    EXPECT_NEAR(left.core_seconds, 2 * cost * 1e-6, 1e-9 * cost * 1e-6);
    EXPECT_NEAR(left.longest_chain, 2 * cost * 1e-6, 1e-9 * cost * 1e-6);
    EXPECT_NEAR(left.on(4), 2 * cost * 1e-6, 1e-9 * cost * 1e-6);  // not half of it
}

}  // namespace
}  // namespace jamsim
