#pragma once
#include <vector>

#include "jamsim/dynamics/model.hpp"
#include "jamsim/force/pair_scatter.hpp"

namespace jamsim {

/// Which dissipative force a massive model uses (thesis §4.6), with w_ij = u_i − u_j +
/// γ̇ [y_i − y_j]_L x̂ the relative lab velocity of a contact and n̂ = r̂_ij:
///   RD:  f_i = −k_d u_i                      (drag against the affine flow, eq. 4.31–4.32)
///   CD:  f_i = −k_d Σ_contacts w_ij           (eq. 4.26–4.28)
///   CDn: f_i = −k_d Σ_contacts (w_ij·n̂) n̂     (normal part only, eq. 4.29)
///   CDt: f_i = −k_d Σ_contacts (w_ij − (w_ij·n̂) n̂)  (tangential part, eq. 4.30)
enum class Damping { RD, CD, CDn, CDt };

/// Largest stable Δt for a massive model: oscillation ωΔt ≤ 1.5 with stiffness up to
/// 8 k_e/d_s² on a small disk; for CD, CDn, CDt (Heun) also a decay rate λΔt ≤ 2 with up to 8
/// damped contacts (RD's drag is integrated exactly and sets no limit).
double sllod_stable_dt(Damping damping, double mass, double kd);

/// Massive disks under the SLLOD equations in sheared coordinates (thesis eq. 4.25):
///   ẋ = u_x − γ u_y,  ẏ = u_y,  u̇_x = (f^el_x + f^dis_x)/m_i − γ̇ u_y,  u̇_y = (f^el_y + f^dis_y)/m_i
/// with m_i = m d_i² (mass of a small disk m, scaled by area). Velocities start at zero (the
/// affine flow).
///  - CD, CDn, CDt: Heun's method on the whole state (x, y, u): second order, the pairwise,
///    position-dependent dissipation evaluated consistently at both stages (two force
///    evaluations per step).
///  - RD: the drag −k_d u_i is one-body and linear, so a symmetric (Strang) splitting
///    B(Δt/2) A(Δt/2) O(Δt) A(Δt/2) B(Δt/2) is second order with one force evaluation per
///    step: B kicks u with the elastic force, A drifts x (with the mid-interval γ, exact for
///    constant u), O solves u̇_x = −γ̇ u_y − c u_x, u̇_y = −c u_y (c = k_d/m_i) exactly:
///    u_y ← e^{−cΔt} u_y, u_x ← e^{−cΔt} (u_x − γ̇ Δt u_y). The forces of the new state are
///    evaluated inside advance() for the closing kick.
class Sllod final : public Model {
  public:
    Sllod(const ReplicaParams& params, Damping damping) : mass_(params.mass), kd_(params.kd), damping_(damping) {}
    void advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t step) override;
    Dissipation dissipation(const System& sys, const ForceField& forces, double rate) const override;

    /// Largest stable Δt estimate for these parameters (elastic and dissipative rates of a
    /// small disk with up to 8 contacts); advance() refuses a larger Δt.
    double stable_dt() const;

    bool leaves_forces_current() const override { return damping_ == Damping::RD; }

  private:
    void advance_heun(System& sys, ForceField& forces, double dt, double rate);
    void advance_split_rd(System& sys, ForceField& forces, double dt, double rate);

    /// Time derivatives (dx, dy, dux, duy) at state (x, y, ux, uy) with elastic forces
    /// (fx, fy) and strain γ, for Heun (CD, CDn, CDt; RD uses advance_split_rd).
    void rates(const System& sys, const ForceField& forces, double gamma, double rate, const std::vector<double>& x,
               const std::vector<double>& y, const std::vector<double>& ux, const std::vector<double>& uy,
               const std::vector<double>& fx, const std::vector<double>& fy);

    double mass_, kd_;
    Damping damping_;
    std::vector<double> dx_, dy_, dux_, duy_, x0_, y0_, ux0_, uy0_, fx1_, fy1_, k1x_, k1y_, k1ux_, k1uy_, fdx_, fdy_;
    HaloScratch halo_;  ///< of the contact damping scatter
};

/// Registrations (src/run/model_registry.cpp).
DynamicsInfo rd_model();
DynamicsInfo cd_model();
DynamicsInfo cdn_model();
DynamicsInfo cdt_model();

}  // namespace jamsim
