#include "jamsim/dynamics/sllod.hpp"

#include <cmath>

#include "jamsim/force/pair_forces.hpp"
#include "jamsim/parallel/reduce.hpp"
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
}  // namespace

double sllod_stable_dt(Damping damping, double m, double kd) {
    // Small disk: the lightest. 8 / m overflows for m < 8 / DBL_MAX (mass = 1e-308 gave a
    // limit of 0); m / 8 then gives the limit, which the first form keeps to the bit elsewhere.
    const double stiffness_over_mass = 8.0 / m;
    const double elastic_limit =
        std::isfinite(stiffness_over_mass) ? 1.5 / std::sqrt(stiffness_over_mass) : 1.5 * std::sqrt(m / 8.0);
    if (damping == Damping::RD) return elastic_limit;  // drag integrated exactly
    const double damping_limit = 2.0 * m / (kd * 8.0);
    return std::min(damping_limit, elastic_limit);
}

double Sllod::stable_dt() const { return sllod_stable_dt(damping_, mass_, kd_); }

namespace {
constexpr std::string_view kSllodParameters[] = {"dt", "kd", "mass"};

template <Damping kDamping> DynamicsInfo sllod_model(std::string_view name, std::string_view summary) {
    return {.name = name,
            .summary = summary,
            .parameters = kSllodParameters,
            .evaluations_per_step = [](const ReplicaParams&) { return kDamping == Damping::RD ? 1 : 2; },
            .stable_dt = [](const ReplicaParams& p) { return sllod_stable_dt(kDamping, p.mass, p.kd); },
            .make = [](const ReplicaParams& p, const RandomKey&) -> std::unique_ptr<Model> {
                return std::make_unique<Sllod>(p, kDamping);
            }};
}
}  // namespace

DynamicsInfo rd_model() {
    return sllod_model<Damping::RD>("RD", "massive (SLLOD), reservoir drag -k_d u_i (eqs. 4.31-4.32)");
}
DynamicsInfo cd_model() {
    return sllod_model<Damping::CD>("CD", "massive (SLLOD), contact dissipation (eqs. 4.26-4.28)");
}
DynamicsInfo cdn_model() {
    return sllod_model<Damping::CDn>("CDn", "massive (SLLOD), normal contact dissipation (eq. 4.29)");
}
DynamicsInfo cdt_model() {
    return sllod_model<Damping::CDt>("CDt", "massive (SLLOD), tangential contact dissipation (eq. 4.30)");
}

void Sllod::rates(const System& sys, const ForceField& forces, double gamma, double rate, const std::vector<double>& x,
                  const std::vector<double>& y, const std::vector<double>& ux, const std::vector<double>& uy,
                  const std::vector<double>& fx, const std::vector<double>& fy) {
    const Particles& p = sys.particles;
    const std::size_t n = p.size();
    fdx_.resize(n);
    fdy_.resize(n);
    // Contact damping (RD never gets here: it uses the splitting). A pair out of contact
    // adds nothing (+0 leaves every sum as it is).
    Box box = sys.box;
    box.set_strain_unwrapped(gamma);
    scatter_pairs(forces.list(), box, x, y, fdx_, fdy_, halo_,
                  [&](std::size_t, std::size_t i, std::size_t j, Vec2 r, bool touching) {
                      if (!touching) return Vec2{0.0, 0.0};
                      const double inv_r = 1.0 / std::sqrt(norm2(r));
                      const Vec2 w{ux[i] - ux[j] + rate * r.y, uy[i] - uy[j]};
                      return contact_damping(damping_, kd_, w, {r.x * inv_r, r.y * inv_r});
                  });
    dx_.resize(n);
    dy_.resize(n);
    dux_.resize(n);
    duy_.resize(n);
    parallel_for(n, [&](std::size_t i) {
        const double inv_m = 1.0 / (mass_ * p.diameter[i] * p.diameter[i]);
        dx_[i] = ux[i] - gamma * uy[i];
        dy_[i] = uy[i];
        dux_[i] = (fx[i] + fdx_[i]) * inv_m - rate * uy[i];
        duy_[i] = (fy[i] + fdy_[i]) * inv_m;
    });
}

void Sllod::advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t) {
    if (dt > stable_dt())
        throw std::runtime_error("SLLOD: time step dt = " + std::to_string(dt) + " exceeds the stable limit " +
                                 std::to_string(stable_dt()) + " for mass " + std::to_string(mass_) + " and kd " +
                                 std::to_string(kd_));
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
        parallel_for(n, [&](std::size_t i) {
            const double h_m = half / (mass_ * p.diameter[i] * p.diameter[i]);
            p.ux[i] += h_m * p.fx[i];
            p.uy[i] += h_m * p.fy[i];
        });
    };
    kick();
    drift(p.x, p.y, p.ux, p.uy, gamma0 + 0.25 * rate * dt, half);  // A, γ at its midpoint
    // O: exact for the drag and the SLLOD coupling; e^{−cΔt} for the two disk sizes.
    // In blocks of disks, each remembering its last diameter's factor (one exp per change).
    const double c_small = kd_ / mass_;
    parallel_for_blocks((n + kReduceBlock - 1) / kReduceBlock, [&](std::size_t b) {
        double d_cached = -1.0, decay = 1.0;
        for (std::size_t i = b * kReduceBlock; i < std::min(n, (b + 1) * kReduceBlock); ++i) {
            if (p.diameter[i] != d_cached) {
                d_cached = p.diameter[i];
                decay = std::exp(-c_small * dt / (d_cached * d_cached));
            }
            p.ux[i] = decay * (p.ux[i] - rate * dt * p.uy[i]);
            p.uy[i] = decay * p.uy[i];
        }
    });
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
    parallel_for(n, [&](std::size_t i) {  // predictor
        p.x[i] = x0_[i] + dt * k1x_[i];
        p.y[i] = y0_[i] + dt * k1y_[i];
        p.ux[i] = ux0_[i] + dt * k1ux_[i];
        p.uy[i] = uy0_[i] + dt * k1uy_[i];
    });
    sys.box.set_strain_unwrapped(gamma1);
    fx1_.resize(n);
    fy1_.resize(n);
    forces.compute_at(sys.box, p.x, p.y, p.diameter, fx1_, fy1_);
    rates(sys, forces, gamma1, rate, p.x, p.y, p.ux, p.uy, fx1_, fy1_);
    const double half = 0.5 * dt;
    parallel_for(n, [&](std::size_t i) {  // corrector
        p.x[i] = x0_[i] + half * (k1x_[i] + dx_[i]);
        p.y[i] = y0_[i] + half * (k1y_[i] + dy_[i]);
        p.ux[i] = ux0_[i] + half * (k1ux_[i] + dux_[i]);
        p.uy[i] = uy0_[i] + half * (k1uy_[i] + duy_[i]);
    });
    apply_strain(sys, forces, gamma1);
}

Dissipation Sllod::dissipation(const System& sys, const ForceField& forces, double rate) const {
    const Particles& p = sys.particles;
    Dissipation d;
    struct Kinetic {
        double energy = 0, kxx = 0, kyy = 0, kxy = 0;
    };
    const Kinetic k = blocked_reduce<Kinetic>(
        p.size(),
        [&](std::size_t lo, std::size_t hi) {
            Kinetic s;
            for (std::size_t i = lo; i < hi; ++i) {
                const double m = mass_ * p.diameter[i] * p.diameter[i];
                s.energy += 0.5 * m * (p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i]);
                s.kxx += m * p.ux[i] * p.ux[i];
                s.kyy += m * p.uy[i] * p.uy[i];
                s.kxy += m * p.ux[i] * p.uy[i];
            }
            return s;
        },
        [](const Kinetic& a, const Kinetic& b) {
            return Kinetic{a.energy + b.energy, a.kxx + b.kxx, a.kyy + b.kyy, a.kxy + b.kxy};
        });
    d.kinetic_energy = k.energy;
    const double area = sys.box.area();
    d.pressure_kinetic = 0.5 * (k.kxx + k.kyy) / area;
    d.shear_stress_kinetic = -k.kxy / area;
    if (damping_ == Damping::RD) {
        d.power = kd_ * static_cast<double>(p.size()) * mean_square_velocity(p);
        return d;
    }
    // Contacts at the current (step-boundary) state: the list is valid for it.
    struct ContactSums {
        double power = 0, vxx = 0, vyy = 0, vyx = 0;
    };
    const ContactSums c = reduce_pairs<ContactSums>(
        forces.list(), sys.box, p.x, p.y,
        [&](ContactSums& s, std::size_t, std::size_t i, std::size_t j, Vec2 r, bool touching) {
            if (!touching) return;
            const Vec2 w{p.ux[i] - p.ux[j] + rate * r.y, p.uy[i] - p.uy[j]};
            const double len = std::sqrt(r.x * r.x + r.y * r.y);
            const Vec2 f = contact_damping(damping_, kd_, w, {r.x / len, r.y / len});
            s.power -= f.x * w.x + f.y * w.y;  // −f·w ≥ 0 for each of the three forms
            s.vxx += r.x * f.x;
            s.vyy += r.y * f.y;
            s.vyx += r.y * f.x;
        },
        [](const ContactSums& a, const ContactSums& b) {
            return ContactSums{a.power + b.power, a.vxx + b.vxx, a.vyy + b.vyy, a.vyx + b.vyx};
        });
    d.power = c.power;
    d.pressure = 0.5 * (c.vxx + c.vyy) / area;
    d.shear_stress = -c.vyx / area;
    return d;
}

}  // namespace jamsim
