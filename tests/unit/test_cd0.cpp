// CD0: the PETSc contact-matrix assembly and solve against a dense Eigen solve built from a
// brute-force contact search over explicit images (contacts across the sheared boundary
// included).
#include <gtest/gtest.h>
#include <petscsys.h>

#include <Eigen/Dense>
#include <cmath>

#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/dynamics/force_field.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using jamsim::testing::image_separation;
using jamsim::testing::random_configuration;

TEST(Cd0, ContactSolveMatchesDenseEigen) {
    // Tight solver tolerance for the comparison (set before the solver is created).
    ASSERT_EQ(PetscOptionsSetValue(nullptr, "-cd0_ksp_rtol", "1e-14"), 0);
    for (const char* solver : {"petsc", "eigen"})
    for (std::int64_t n : {40, 300})
        for (double gamma : {-0.45, 0.0, 0.3}) {
            System sys = random_configuration(n, 0.86, gamma, 17);
            ForceField ff(potential::make_soft_sphere(2.0), 0.3);
            ff.compute(sys);
            const double rate = 0.01, kd = 1.5, delta = 1e-2;
            ModelParams params{kd, Integrator::Euler, delta};
            params.solver = solver;
            Cd0 model(params);
            model.prepare(sys, ff, rate);
            const Particles& p = sys.particles;
            const auto N = static_cast<Eigen::Index>(p.size());
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N, N);
            Eigen::VectorXd bx(N), by(N);
            for (Eigen::Index i = 0; i < N; ++i) {
                bx[i] = p.fx[static_cast<std::size_t>(i)] / kd;
                by[i] = p.fy[static_cast<std::size_t>(i)] / kd;
                A(i, i) = delta;
            }
            int crossing = 0;
            for (std::size_t i = 0; i < p.size(); ++i)
                for (std::size_t j = i + 1; j < p.size(); ++j)
                    for (int m = -2; m <= 2; ++m)
                        for (int k = -2; k <= 2; ++k) {
                            const auto r = image_separation(sys, i, j, m, k);
                            const double d = 0.5 * (p.diameter[i] + p.diameter[j]);
                            if (r.rx * r.rx + r.ry * r.ry >= d * d) continue;
                            const auto a = static_cast<Eigen::Index>(i), b = static_cast<Eigen::Index>(j);
                            A(a, a) += 1;
                            A(b, b) += 1;
                            A(a, b) -= 1;
                            A(b, a) -= 1;
                            bx[a] -= rate * r.ry;
                            bx[b] += rate * r.ry;
                            crossing += k != 0;
                        }
            ASSERT_GT(crossing, 0) << "no contact across the sheared boundary";
            const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
            const Eigen::VectorXd ux = ldlt.solve(bx), uy = ldlt.solve(by);
            const double scale = std::max(ux.cwiseAbs().maxCoeff(), uy.cwiseAbs().maxCoeff());
            for (Eigen::Index i = 0; i < N; ++i) {
                EXPECT_NEAR(p.ux[static_cast<std::size_t>(i)], ux[i], 1e-9 * scale) << solver;
                EXPECT_NEAR(p.uy[static_cast<std::size_t>(i)], uy[i], 1e-9 * scale);
            }
            // Σ_i (A u)_i = δ Σ_i u_i = Σ_i b_i = 0: no net non-affine motion.
            double sx = 0, sy = 0;
            for (std::size_t i = 0; i < p.size(); ++i) {
                sx += p.ux[i];
                sy += p.uy[i];
            }
            EXPECT_NEAR(sx / static_cast<double>(n), 0.0, 1e-9 * scale);
            EXPECT_NEAR(sy / static_cast<double>(n), 0.0, 1e-9 * scale);
        }
}
