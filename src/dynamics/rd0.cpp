#include "jamsim/dynamics/rd0.hpp"

namespace jamsim {

void Rd0::advance(System& sys, ForceField& forces, double dt, double rate) {
    Particles& p = sys.particles;
    const std::size_t n = p.size();
    const double step = dt / params_.kd;
    const double gamma0 = sys.box.strain();
    const double gamma1 = gamma0 + rate * dt;
    if (params_.integrator == Integrator::Euler) {
        drift(p.x, p.y, p.fx, p.fy, gamma0, step);  // u = f/k_d
        apply_strain(sys, forces, gamma1);
        return;
    }
    // Heun: predictor with the forces of the current state (already in fx, fy) ...
    x0_.assign(p.x.begin(), p.x.end());
    y0_.assign(p.y.begin(), p.y.end());
    fx1_.resize(n);
    fy1_.resize(n);
    drift(p.x, p.y, p.fx, p.fy, gamma0, step);
    // ... corrector with the forces at the predicted positions and the end-of-step strain.
    sys.box.set_strain_unwrapped(gamma1);
    forces.compute_at(sys.box, p.x, p.y, p.diameter, fx1_, fy1_);
    const double half = 0.5 * step;
    for (std::size_t i = 0; i < n; ++i) {
        p.x[i] = x0_[i] + half * ((p.fx[i] - gamma0 * p.fy[i]) + (fx1_[i] - gamma1 * fy1_[i]));
        p.y[i] = y0_[i] + half * (p.fy[i] + fy1_[i]);
    }
    apply_strain(sys, forces, gamma1);
}

void Rd0::store_velocities(System& sys) const {
    Particles& p = sys.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        p.ux[i] = p.fx[i] / params_.kd;
        p.uy[i] = p.fy[i] / params_.kd;
    }
}

Dissipation Rd0::dissipation(const System& sys, const ForceField& /*forces*/,
                             double /*rate*/) const {
    return {params_.kd * static_cast<double>(sys.particles.size()) * nonaffine_velocity_sq(sys),
            0.0, 0.0};
}

double Rd0::nonaffine_velocity_sq(const System& sys) const {
    const Particles& p = sys.particles;
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.fx[i] * p.fx[i] + p.fy[i] * p.fy[i];
    return p.size() ? sum / (params_.kd * params_.kd * static_cast<double>(p.size())) : 0.0;
}

} // namespace jamsim
