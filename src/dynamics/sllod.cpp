#include "jamsim/dynamics/sllod.hpp"

#include <cmath>

#include "jamsim/force/pair_forces.hpp"
#include <stdexcept>
#include <string>

namespace jamsim {

namespace {
/// Dissipative force on i from j for relative velocity w, contact direction n (unit).
inline Vec2 contact_damping(Damping d, double kd, Vec2 w, Vec2 n) {
    const double wn = w.x * n.x + w.y * n.y;
    switch (d) {
    case Damping::CD: return {-kd * w.x, -kd * w.y};
    case Damping::CDn: return {-kd * wn * n.x, -kd * wn * n.y};
    case Damping::CDt: return {-kd * (w.x - wn * n.x), -kd * (w.y - wn * n.y)};
    case Damping::RD: break;
    }
    return {0.0, 0.0};
}
} // namespace

double sllod_stable_dt(Damping damping, double m, double kd) {
    const double elastic_limit = 1.5 / std::sqrt(8.0 / m);  // small disk: the lightest
    if (damping == Damping::RD) return elastic_limit;        // drag integrated exactly
    const double damping_limit = 2.0 * m / (kd * 8.0);
    return std::min(damping_limit, elastic_limit);
}

double Sllod::stable_dt() const { return sllod_stable_dt(damping_, params_.mass, params_.kd); }

void Sllod::rates(const System& sys, const ForceField& forces, double gamma, double rate,
                  const std::vector<double>& x, const std::vector<double>& y,
                  const std::vector<double>& ux, const std::vector<double>& uy,
                  const std::vector<double>& fx, const std::vector<double>& fy) {
    const Particles& p = sys.particles;
    const std::size_t n = p.size();
    fdx_.assign(n, 0.0);
    fdy_.assign(n, 0.0);
    {  // contact damping (RD never gets here: it uses the splitting)
        const NeighborList& list = forces.list();
        const auto owner = list.owner(), neighbor = list.neighbor();
        const auto sx = list.shift_x(), sy = list.shift_y(), contact = list.contact();
        Box box = sys.box;
        box.set_strain_unwrapped(gamma);
        for (std::size_t k = 0; k < list.size(); ++k) {
            const auto i = static_cast<std::size_t>(owner[k]), j = static_cast<std::size_t>(neighbor[k]);
            const Vec2 r = box.lab(x[i] - x[j] + sx[k], y[i] - y[j] + sy[k]);
            const double r2 = norm2(r);
            if (r2 >= contact[k] * contact[k]) continue;
            const double inv_r = 1.0 / std::sqrt(r2);
            const Vec2 w{ux[i] - ux[j] + rate * r.y, uy[i] - uy[j]};
            const Vec2 f = contact_damping(damping_, params_.kd, w, {r.x * inv_r, r.y * inv_r});
            fdx_[i] += f.x;
            fdy_[i] += f.y;
            fdx_[j] -= f.x;
            fdy_[j] -= f.y;
        }
    }
    dx_.resize(n);
    dy_.resize(n);
    dux_.resize(n);
    duy_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double inv_m = 1.0 / (params_.mass * p.diameter[i] * p.diameter[i]);
        dx_[i] = ux[i] - gamma * uy[i];
        dy_[i] = uy[i];
        dux_[i] = (fx[i] + fdx_[i]) * inv_m - rate * uy[i];
        duy_[i] = (fy[i] + fdy_[i]) * inv_m;
    }
}

void Sllod::advance(System& sys, ForceField& forces, double dt, double rate) {
    if (dt > stable_dt())
        throw std::runtime_error(std::string(name_) + ": time step dt = " + std::to_string(dt) +
                                 " exceeds the stable limit " + std::to_string(stable_dt()) +
                                 " for mass " + std::to_string(params_.mass) + " and kd " +
                                 std::to_string(params_.kd));
    if (damping_ == Damping::RD)
        advance_split_rd(sys, forces, dt, rate);
    else
        advance_heun(sys, forces, dt, rate);
}

void Sllod::advance_split_rd(System& sys, ForceField& forces, double dt, double rate) {
    Particles& p = sys.particles;
    const std::size_t n = p.size();
    const double half = 0.5 * dt, gamma0 = sys.box.strain();
    auto kick = [&] {  // B(Δt/2) with the forces in p.fx, p.fy
        for (std::size_t i = 0; i < n; ++i) {
            const double h_m = half / (params_.mass * p.diameter[i] * p.diameter[i]);
            p.ux[i] += h_m * p.fx[i];
            p.uy[i] += h_m * p.fy[i];
        }
    };
    kick();
    drift(p.x, p.y, p.ux, p.uy, gamma0 + 0.25 * rate * dt, half);  // A, γ at its midpoint
    // O: exact for the drag and the SLLOD coupling; e^{−cΔt} for the two disk sizes.
    const double c_small = params_.kd / params_.mass;
    double d_cached = -1.0, decay = 1.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (p.diameter[i] != d_cached) {
            d_cached = p.diameter[i];
            decay = std::exp(-c_small * dt / (d_cached * d_cached));
        }
        p.ux[i] = decay * (p.ux[i] - rate * dt * p.uy[i]);
        p.uy[i] = decay * p.uy[i];
    }
    drift(p.x, p.y, p.ux, p.uy, gamma0 + 0.75 * rate * dt, half);
    apply_strain(sys, forces, gamma0 + rate * dt);
    forces.compute(sys, Tally::ForcesOnly);
    kick();
}

void Sllod::advance_heun(System& sys, ForceField& forces, double dt, double rate) {
    Particles& p = sys.particles;
    const std::size_t n = p.size();
    const double gamma0 = sys.box.strain(), gamma1 = gamma0 + rate * dt;
    x0_ = p.x;
    y0_ = p.y;
    ux0_ = p.ux;
    uy0_ = p.uy;
    rates(sys, forces, gamma0, rate, x0_, y0_, ux0_, uy0_, p.fx, p.fy);
    k1x_ = dx_;
    k1y_ = dy_;
    k1ux_ = dux_;
    k1uy_ = duy_;
    for (std::size_t i = 0; i < n; ++i) {  // predictor
        p.x[i] = x0_[i] + dt * k1x_[i];
        p.y[i] = y0_[i] + dt * k1y_[i];
        p.ux[i] = ux0_[i] + dt * k1ux_[i];
        p.uy[i] = uy0_[i] + dt * k1uy_[i];
    }
    sys.box.set_strain_unwrapped(gamma1);
    fx1_.resize(n);
    fy1_.resize(n);
    forces.compute_at(sys.box, p.x, p.y, p.diameter, fx1_, fy1_);
    rates(sys, forces, gamma1, rate, p.x, p.y, p.ux, p.uy, fx1_, fy1_);
    const double half = 0.5 * dt;
    for (std::size_t i = 0; i < n; ++i) {  // corrector
        p.x[i] = x0_[i] + half * (k1x_[i] + dx_[i]);
        p.y[i] = y0_[i] + half * (k1y_[i] + dy_[i]);
        p.ux[i] = ux0_[i] + half * (k1ux_[i] + dux_[i]);
        p.uy[i] = uy0_[i] + half * (k1uy_[i] + duy_[i]);
    }
    apply_strain(sys, forces, gamma1);
}

double Sllod::nonaffine_velocity_sq(const System& sys) const {
    const Particles& p = sys.particles;
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i];
    return p.size() ? sum / static_cast<double>(p.size()) : 0.0;
}

Dissipation Sllod::dissipation(const System& sys, const ForceField& forces,
                               double rate) const {
    const Particles& p = sys.particles;
    Dissipation d;
    double kxx = 0, kyy = 0, kxy = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double m = params_.mass * p.diameter[i] * p.diameter[i];
        d.kinetic_energy += 0.5 * m * (p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i]);
        kxx += m * p.ux[i] * p.ux[i];
        kyy += m * p.uy[i] * p.uy[i];
        kxy += m * p.ux[i] * p.uy[i];
    }
    const double area = sys.box.area();
    d.pressure_kinetic = 0.5 * (kxx + kyy) / area;
    d.shear_stress_kinetic = -kxy / area;
    if (damping_ == Damping::RD) {
        d.power = params_.kd * static_cast<double>(p.size()) * nonaffine_velocity_sq(sys);
        return d;
    }
    // Contacts at the current (step-boundary) state: the list is valid for it.
    double vxx = 0, vyy = 0, vyx = 0;
    for (const Contact& c : find_contacts(forces.list(), sys.box, p.x, p.y)) {
        const Vec2 w{p.ux[c.i] - p.ux[c.j] + rate * c.ry, p.uy[c.i] - p.uy[c.j]};
        const double r = std::sqrt(c.rx * c.rx + c.ry * c.ry);
        const Vec2 f = contact_damping(damping_, params_.kd, w, {c.rx / r, c.ry / r});
        d.power -= f.x * w.x + f.y * w.y;  // −f·w ≥ 0 for each of the three forms
        vxx += c.rx * f.x;
        vyy += c.ry * f.y;
        vyx += c.ry * f.x;
    }
    d.pressure = 0.5 * (vxx + vyy) / area;
    d.shear_stress = -vyx / area;
    return d;
}

} // namespace jamsim
