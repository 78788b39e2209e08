#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "jamsim/core/box.hpp"
#include "jamsim/core/rng.hpp"

using namespace jamsim;

// The minimum image must equal the shortest of the explicit images (x + mL, y + nL)
// mapped to the lab frame, for every γ in the allowed range.
TEST(Box, MinImageMatchesExplicitImages) {
    const double L = 10.0;
    const RngStream rng(1, 0, RngPurpose::TestConfiguration);
    for (double gamma : {-0.5, -0.49, -0.2, 0.0, 0.3, 0.49}) {
        Box box(L, 0.0);
        box.set_strain_unwrapped(gamma);
        for (std::uint32_t k = 0; k < 2000; ++k) {
            const auto u = rng.uniform2(k), v = rng.uniform2(k, 1);
            const double dx = (u[0] - 0.5) * 3 * L, dy = (u[1] - 0.5) * 3 * L;
            double best = 1e300;
            for (int m = -4; m <= 4; ++m)
                for (int n = -4; n <= 4; ++n) {
                    const double ry = dy + n * L, rx = dx + m * L + gamma * ry;
                    best = std::min(best, rx * rx + ry * ry);
                }
            const Vec2 r = box.min_image(dx, dy);
            // Exact whenever the shortest image is shorter than L/2 (all the force loop needs).
            if (best < 0.25 * L * L) { EXPECT_NEAR(norm2(r), best, 1e-9) << "gamma " << gamma; }
            (void)v;
        }
    }
}

TEST(Box, StrainWrapKeepsLabPositions) {
    const double L = 8.0;
    Box box(L, 0.49);
    std::vector<double> x = {0.1, 3.0, 7.9}, y = {0.2, 4.0, 7.5};
    std::vector<double> lab_before;
    box.set_strain_unwrapped(0.51);
    for (std::size_t i = 0; i < x.size(); ++i) lab_before.push_back(box.lab_x(x[i], y[i]));
    const int k = box.finish_shear();
    EXPECT_EQ(k, 1);
    EXPECT_NEAR(box.strain(), -0.49, 1e-15);
    box.remap_after_wrap(k, x, y);
    for (std::size_t i = 0; i < x.size(); ++i) {
        // same lab position modulo L in x
        const double diff = box.lab_x(x[i], y[i]) - lab_before[i];
        EXPECT_NEAR(diff - L * std::round(diff / L), 0.0, 1e-12);
    }
}

TEST(Box, StrainWrapNegativeDirection) {
    Box box(5.0, -0.49);
    box.set_strain_unwrapped(-0.51);
    EXPECT_EQ(box.finish_shear(), -1);
    EXPECT_NEAR(box.strain(), 0.49, 1e-15);
}

TEST(Box, WrapIntoCell) {
    const Box box(4.0);
    double x = -0.5, y = 9.0;
    box.wrap_into_cell(x, y);
    EXPECT_DOUBLE_EQ(x, 3.5);
    EXPECT_DOUBLE_EQ(y, 1.0);
    x = -1e-18;
    y = 4.0;
    box.wrap_into_cell(x, y);
    EXPECT_GE(x, 0.0);
    EXPECT_LT(x, 4.0);
    EXPECT_GE(y, 0.0);
    EXPECT_LT(y, 4.0);
}
