#include "jamsim/dynamics/cd0.hpp"

namespace jamsim {

void Cd0::solve(const ForceField& forces, const Box& box, std::span<const double> x,
                std::span<const double> y, std::span<const double> fx,
                std::span<const double> fy, double rate, std::span<double> ux,
                std::span<double> uy) {
    const std::size_t n = x.size();
    // Candidate pairs = the neighbour list (its pattern changes only at a rebuild).
    const NeighborList& list = forces.list();
    if (list.builds() != pairs_version_) {
        pairs_.resize(list.size());
        for (std::size_t k = 0; k < list.size(); ++k)
            pairs_[k] = {list.owner()[k], list.neighbor()[k]};
        pairs_version_ = list.builds();
    }
    in_contact_.assign(list.size(), 0);
    contact_rx_.resize(list.size());
    contact_ry_.resize(list.size());
    bx_.resize(n);
    by_.resize(n);
    const double inv_kd = 1.0 / params_.kd;
    for (std::size_t i = 0; i < n; ++i) {
        bx_[i] = fx[i] * inv_kd;
        by_[i] = fy[i] * inv_kd;
    }
    // Contacts and the affine part of the contact drag: −γ̇ Σ_j [y_i − y_j] (k_d cancels).
    const auto sx = list.shift_x(), sy = list.shift_y(), contact = list.contact();
    for (std::size_t k = 0; k < list.size(); ++k) {
        const auto i = static_cast<std::size_t>(pairs_[k].i), j = static_cast<std::size_t>(pairs_[k].j);
        const Vec2 r = box.lab(x[i] - x[j] + sx[k], y[i] - y[j] + sy[k]);
        contact_rx_[k] = r.x;
        contact_ry_[k] = r.y;
        if (norm2(r) >= contact[k] * contact[k]) continue;
        in_contact_[k] = 1;
        bx_[i] -= rate * r.y;
        bx_[j] += rate * r.y;
    }
    if (params_.solver == "eigen" || (params_.solver == "auto" && n <= auto_eigen_max_n)) {
        if (!eigen_) eigen_ = std::make_unique<linalg::EigenContactSolver>(n, params_.delta);
        last_ = eigen_->solve(pairs_, in_contact_, pairs_version_, bx_, by_, ux, uy);
    } else {
        if (!solver_)
            solver_ = std::make_unique<linalg::ContactSolver>(n, params_.delta, params_.petsc_options);
        last_ = solver_->solve(pairs_, in_contact_, pairs_version_, bx_, by_, ux, uy);
    }
}

void Cd0::prepare(System& sys, ForceField& forces, double rate) {
    Particles& p = sys.particles;
    solve(forces, sys.box, p.x, p.y, p.fx, p.fy, rate, p.ux, p.uy);
}

void Cd0::advance(System& sys, ForceField& forces, double dt, double rate) {
    Particles& p = sys.particles;
    const std::size_t n = p.size();
    const double gamma0 = sys.box.strain();
    const double gamma1 = gamma0 + rate * dt;
    if (params_.integrator == Integrator::Euler) {
        drift(p.x, p.y, p.ux, p.uy, gamma0, dt);
        apply_strain(sys, forces, gamma1);
        return;
    }
    x0_.assign(p.x.begin(), p.x.end());
    y0_.assign(p.y.begin(), p.y.end());
    fx1_.resize(n);
    fy1_.resize(n);
    ux1_.assign(p.ux.begin(), p.ux.end());  // warm start of the second solve
    uy1_.assign(p.uy.begin(), p.uy.end());
    drift(p.x, p.y, p.ux, p.uy, gamma0, dt);
    sys.box.set_strain_unwrapped(gamma1);
    forces.compute_at(sys.box, p.x, p.y, p.diameter, fx1_, fy1_);
    solve(forces, sys.box, p.x, p.y, fx1_, fy1_, rate, ux1_, uy1_);
    const double half = 0.5 * dt;
    for (std::size_t i = 0; i < n; ++i) {
        p.x[i] = x0_[i] + half * ((p.ux[i] - gamma0 * p.uy[i]) + (ux1_[i] - gamma1 * uy1_[i]));
        p.y[i] = y0_[i] + half * (p.uy[i] + uy1_[i]);
    }
    apply_strain(sys, forces, gamma1);
}

Dissipation Cd0::dissipation(const System& sys, const ForceField& /*forces*/,
                             double rate) const {
    const Particles& p = sys.particles;
    Dissipation d;
    double vxx = 0, vyy = 0, vyx = 0;
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
        if (!in_contact_[k]) continue;
        const auto i = static_cast<std::size_t>(pairs_[k].i), j = static_cast<std::size_t>(pairs_[k].j);
        const double wx = p.ux[i] - p.ux[j] + rate * contact_ry_[k];  // relative lab velocity
        const double wy = p.uy[i] - p.uy[j];
        d.power += params_.kd * (wx * wx + wy * wy);
        const double fx = -params_.kd * wx, fy = -params_.kd * wy;  // on i from j
        vxx += contact_rx_[k] * fx;
        vyy += contact_ry_[k] * fy;
        vyx += contact_ry_[k] * fx;
    }
    d.power += params_.kd * params_.delta * static_cast<double>(p.size()) * nonaffine_velocity_sq(sys);
    d.pressure = 0.5 * (vxx + vyy) / sys.box.area();
    d.shear_stress = -vyx / sys.box.area();
    return d;
}

double Cd0::nonaffine_velocity_sq(const System& sys) const {
    const Particles& p = sys.particles;
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i];
    return p.size() ? sum / static_cast<double>(p.size()) : 0.0;
}

} // namespace jamsim
