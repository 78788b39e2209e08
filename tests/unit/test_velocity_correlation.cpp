#include <gtest/gtest.h>

#include <cmath>

#include "jamsim/observe/velocity_correlation.hpp"

using namespace jamsim;

// A row of disks one unit apart along x at the same y, u_y alternating +1/−1: g_y = −1 at
// odd distances, +1 at even ones; a second row far away in y must not contribute. The row
// is sheared (γ = 0.3) and straddles the periodic x boundary.
TEST(VelocityCorrelation, AlternatingRow) {
    const double L = 20.0;
    Particles p;
    p.resize(40);
    for (std::size_t i = 0; i < 40; ++i) {
        const bool second_row = i >= 20;
        const double y = second_row ? 10.3 : 0.2;
        const double lab_x = std::fmod(static_cast<double>(i % 20) + 15.5, L);
        p.y[i] = y;
        p.x[i] = lab_x - 0.3 * y;  // sheared coordinate for γ = 0.3
        p.diameter[i] = 1.0;
        p.tag[i] = static_cast<std::int32_t>(i);
        p.uy[i] = second_row ? 7.0 : ((i % 2) ? 1.0 : -1.0);
    }
    System sys{p, Box(L)};
    sys.box.set_strain_unwrapped(0.3);
    VelocityCorrelation c(L, 0.42, 1.0);  // integer distances d/0.42 stay clear of bin edges
    c.accumulate(sys);
    const auto x = c.bin_centres();
    const auto g = c.g();
    // <u_y^2> over both rows: (20·1 + 20·49)/40 = 25; row pairs give ±1 (second row: 49)
    const double norm = 25.0;
    int checked = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        const double d = std::round(x[k]);
        if (std::floor(d / 0.42) != static_cast<double>(k) || d < 1 || d > 9) {
            EXPECT_TRUE(std::isnan(g[k])) << x[k];
            continue;
        }
        // each distance d < 10 appears for 20 pairs in each row (periodic); first row ±1,
        // second row 49: mean over both rows
        const double first = (static_cast<int>(d) % 2) ? -1.0 : 1.0;
        EXPECT_NEAR(g[k], 0.5 * (first + 49.0) / norm, 1e-12) << "x = " << x[k];
        ++checked;
    }
    EXPECT_GE(checked, 9);
}
