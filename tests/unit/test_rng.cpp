#include <gtest/gtest.h>

#include <set>

#include "jamsim/core/rng.hpp"
#include "jamsim/core/system.hpp"

using namespace jamsim;

// Known-answer vectors of Philox4x32-10 from the Random123 distribution (kat_vectors).
TEST(Philox, KnownAnswerZero) {
    const auto r = philox4x32({0, 0, 0, 0}, {0, 0});
    EXPECT_EQ(r[0], 0x6627e8d5u);
    EXPECT_EQ(r[1], 0xe169c58du);
    EXPECT_EQ(r[2], 0xbc57ac4cu);
    EXPECT_EQ(r[3], 0x9b00dbd8u);
}

TEST(Philox, KnownAnswerOnes) {
    const auto r = philox4x32({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}, {0xffffffffu, 0xffffffffu});
    EXPECT_EQ(r[0], 0x408f276du);
    EXPECT_EQ(r[1], 0x41c83b0eu);
    EXPECT_EQ(r[2], 0xa20bc7c6u);
    EXPECT_EQ(r[3], 0x6d5451fdu);
}

TEST(RngStream, KeyedByReplicaAndPurpose) {
    const RngStream a(42, 3, RngPurpose::InitialPositions);
    const RngStream b(42, 3, RngPurpose::InitialPositions);
    const RngStream other_replica(42, 4, RngPurpose::InitialPositions);
    const RngStream other_purpose(42, 3, RngPurpose::TestConfiguration);
    const RngStream other_seed(43, 3, RngPurpose::InitialPositions);
    for (std::uint32_t i = 0; i < 100; ++i) {
        EXPECT_EQ(a.uniform2(i), b.uniform2(i));
        EXPECT_NE(a.uniform2(i), other_replica.uniform2(i));
        EXPECT_NE(a.uniform2(i), other_purpose.uniform2(i));
        EXPECT_NE(a.uniform2(i), other_seed.uniform2(i));
    }
}

TEST(RngStream, UniformMeanAndRange) {
    // 2e5 draws: the mean of U(0,1) has standard error sqrt(1/12/2e5) = 6.5e-4; allow 5 sigma.
    const RngStream s(7, 0, RngPurpose::TestConfiguration);
    double sum = 0.0;
    const std::uint32_t n = 100000;
    for (std::uint32_t i = 0; i < n; ++i) {
        const auto u = s.uniform2(i);
        for (double v : u) {
            ASSERT_GE(v, 0.0);
            ASSERT_LT(v, 1.0);
            sum += v;
        }
    }
    EXPECT_NEAR(sum / (2.0 * n), 0.5, 5 * std::sqrt(1.0 / 12.0 / (2.0 * n)));
}

TEST(RandomSystem, SameInputsSameBitsAndRequestedPhi) {
    const System a = random_system(1024, 0.84, SizeMix{1.4}, 5, 0);
    const System b = random_system(1024, 0.84, SizeMix{1.4}, 5, 0);
    EXPECT_EQ(a.particles.x, b.particles.x);
    EXPECT_EQ(a.particles.y, b.particles.y);
    EXPECT_NEAR(packing_fraction(a.particles, a.box), 0.84, 1e-14);
    int large = 0;
    for (double d : a.particles.diameter) large += d == 1.4;
    EXPECT_EQ(large, 512);
    const System c = random_system(1024, 0.84, SizeMix{1.4}, 6, 0);
    EXPECT_NE(a.particles.x, c.particles.x);
}

TEST(RandomSystem, RejectsOddNForMixture) {
    EXPECT_THROW(random_system(11, 0.8, SizeMix{1.4}, 1, 0), std::invalid_argument);
    EXPECT_NO_THROW(random_system(11, 0.8, SizeMix{1.0}, 1, 0));
}
