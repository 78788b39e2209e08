#pragma once
#include <memory>
#include <vector>

#include "jamsim/dynamics/model.hpp"
#include "jamsim/dynamics/overdamped_step.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/neighbor/sub_list.hpp"

namespace jamsim {

/// CD0: Durian's overdamped bubble model with contact dissipation (thesis §4.5.1).
/// Force balance per disk: f_i^el − k_d Σ_contacts (v_i − v_j) − k_0 u_i = 0 with
/// v_i − v_j = u_i − u_j + γ̇ [y_i − y_j]_L x̂, which gives the contact-matrix systems
///   A u_x = (f_x − k_d γ̇ Σ_j [y_i − y_j]_L) / k_d,   A u_y = f_y / k_d     (eqs. 4.17–4.18)
/// with A_ii = z_i + δ, A_ij = −1 per contact, δ = k_0/k_d. The substrate drag −k_0 u_i
/// acts on the *non-affine* velocity (drag relative to the shear flow, as in RD0): written
/// literally, eq. 4.16 drags towards zero lab velocity, a force that grows with y_i and jumps
/// when a disk crosses the Lees–Edwards boundary. Positions advance with eq. 4.19,
/// ẋ = u_x − γ u_y, ẏ = u_y (Euler, or Heun with a second solve). The contact matrix's
/// candidate pairs are the neighbour list's within d_ij + skin/3 (a SubList): a thinner
/// pattern than the list's, so less fill and shorter update paths in the solver's factor.
class Cd0 final : public Model {
  public:
    explicit Cd0(const ReplicaParams& params)
        : kd_(params.kd), delta_(params.delta), heun_(params.integrator == "heun"), backend_(params.solver),
          petsc_options_(params.petsc_options), candidates_(candidate_skin(params)) {}
    void prepare(System& sys, ForceField& forces, double rate) override;
    void advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t step) override;
    /// P = k_d Σ_contacts |u_i − u_j + γ̇ [y_i − y_j] x̂|² + k_0 Σ |u_i|²; the contact
    /// dissipative forces f^dis_ij = −k_d (u_i − u_j + γ̇ r_ij,y x̂) give the stress.
    Dissipation dissipation(const System& sys, const ForceField& forces, double rate) const override;

    /// Krylov iterations of the most recent solve (diagnostics, benchmarks).
    linalg::SolveInfo last_solve() const { return last_; }

    /// Candidate lists so far (each a new pattern for the contact solver).
    std::size_t candidate_lists() const { return candidates_.builds(); }

    double solver_iterations() const override { return 0.5 * (last_.iterations_x + last_.iterations_y); }

  private:
    /// Solve for u at positions (x, y) with forces (fx, fy) into (ux, uy).
    void solve(const ForceField& forces, const Box& box, std::span<const double> x, std::span<const double> y,
               std::span<const std::int32_t> tag, std::span<const double> fx, std::span<const double> fy, double rate,
               std::span<double> ux, std::span<double> uy);

    double kd_, delta_;
    bool heun_;
    std::string backend_, petsc_options_;
    linalg::SolveInfo last_;
    std::unique_ptr<linalg::ContactSolver> solver_;
    /// The skin of the contact matrix's candidate pairs: skin/3 (campaigns/models.md's CD0 section
    /// gives the measurements behind the choice).
    static double candidate_skin(const ReplicaParams& params);
    SubList candidates_;
    std::vector<linalg::ContactPair> pairs_;
    std::vector<std::uint8_t> in_contact_;
    std::size_t pairs_version_ = static_cast<std::size_t>(-1);
    OverdampedScratch scratch_;
    std::vector<double> bx_, by_, fx1_, fy1_, ux1_, uy1_, sum_ry_;
};

/// CD0's start protocol (DynamicsInfo::relax_start): random positions at φ overlap so much
/// that the first contact solves see several times the contacts of a sheared state and
/// change most of them every step, and the updated factor's fill, with it the replica's
/// memory, grows far beyond the steady state's (peak RSS 632 MB against 166 MB at N = 65536,
/// about 10.5 GB against 0.37 GB at 262144; tests/bench/cd0_solver.md, "CD0's start"). So the random start is first
/// relaxed
/// by kCd0StartRelaxTime of RD0 dynamics without shear (reservoir drag k_d, Euler, Δt =
/// min(dt, half RD0's stable Δt), a fixed number of steps): the energy falls about 50-fold
/// (N = 1024, φ = 0.84) and the contact solves start near a packing. Deterministic, and the
/// same bits on any thread count (RD0's kernel).
void relax_cd0_start(System& sys, const ReplicaParams& p);
/// The time of that relaxation, in units of k_d/k_e (τ at k_d = 1).
inline constexpr double kCd0StartRelaxTime = 20.0;

/// Registration (src/run/model_registry.cpp).
DynamicsInfo cd0_model();

}  // namespace jamsim
