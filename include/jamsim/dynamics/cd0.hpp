#pragma once
#include <memory>
#include <vector>

#include "jamsim/dynamics/model.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/linalg/eigen_contact_solver.hpp"

namespace jamsim {

/// CD0: Durian's overdamped bubble model with contact dissipation (thesis §4.5.1).
/// Force balance per disk: f_i^el − k_d Σ_contacts (v_i − v_j) − k_0 u_i = 0 with
/// v_i − v_j = u_i − u_j + γ̇ [y_i − y_j]_L x̂, which gives the contact-matrix systems
///   A u_x = (f_x − k_d γ̇ Σ_j [y_i − y_j]_L) / k_d,   A u_y = f_y / k_d     (eqs. 4.17–4.18)
/// with A_ii = z_i + δ, A_ij = −1 per contact, δ = k_0/k_d. The substrate drag −k_0 u_i
/// acts on the *non-affine* velocity (drag relative to the shear flow, as in RD0): written
/// literally, eq. 4.16 drags towards zero lab velocity, a force that grows with y_i and jumps
/// when a disk crosses the Lees–Edwards boundary. Positions advance with eq. 4.19,
/// ẋ = u_x − γ u_y, ẏ = u_y (Euler, or Heun with a second solve).
class Cd0 final : public Model {
  public:
    explicit Cd0(const ModelParams& params) : params_(params) {}
    std::string_view name() const override { return "CD0"; }
    void prepare(System& sys, ForceField& forces, double rate) override;
    void advance(System& sys, ForceField& forces, double dt, double rate) override;
    double nonaffine_velocity_sq(const System& sys) const override;
    /// P = k_d Σ_contacts |u_i − u_j + γ̇ [y_i − y_j] x̂|² + k_0 Σ |u_i|²; the contact
    /// dissipative forces f^dis_ij = −k_d (u_i − u_j + γ̇ r_ij,y x̂) give the stress.
    Dissipation dissipation(const System& sys, const ForceField& forces,
                            double rate) const override;

    /// Krylov iterations of the most recent solve (diagnostics, benchmarks).
    linalg::SolveInfo last_solve() const { return last_; }
    /// `solver = "auto"` uses Eigen (factor updated in place) up to this N, the largest size
    /// measured, and PETSc above (jamsim_bench_cd0 at φ = 0.84, per step: Eigen 61 µs against
    /// PETSc 267 µs at N = 1024, 0.35 ms against 3.4 ms at 4096, 3.2 ms against 36 ms at 16384,
    /// Eigen 48 ms at 65536).
    static constexpr std::size_t auto_eigen_max_n = 65536;

    double solver_iterations() const override {
        return 0.5 * (last_.iterations_x + last_.iterations_y);
    }

  private:
    /// Solve for u at positions (x, y) with forces (fx, fy) into (ux, uy).
    void solve(const ForceField& forces, const Box& box, std::span<const double> x,
               std::span<const double> y, std::span<const double> fx,
               std::span<const double> fy, double rate, std::span<double> ux,
               std::span<double> uy);

    ModelParams params_;
    linalg::SolveInfo last_;
    std::unique_ptr<linalg::ContactSolver> solver_;
    std::unique_ptr<linalg::EigenContactSolver> eigen_;
    std::vector<linalg::ContactPair> pairs_;
    std::vector<std::uint8_t> in_contact_;
    std::vector<double> contact_rx_, contact_ry_;  // lab separation of each candidate pair
    std::size_t pairs_version_ = static_cast<std::size_t>(-1);
    std::vector<double> bx_, by_, x0_, y0_, fx1_, fy1_, ux1_, uy1_;
};

} // namespace jamsim
