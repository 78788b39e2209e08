#include "jamsim/dynamics/cd0.hpp"

#include <cmath>

#include "jamsim/dynamics/overdamped_stability.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

void Cd0::solve(const ForceField& forces, const Box& box, std::span<const double> x, std::span<const double> y,
                std::span<const std::int32_t> tag, std::span<const double> fx, std::span<const double> fy, double rate,
                std::span<double> ux, std::span<double> uy) {
    const std::size_t n = x.size();
    // Candidate pairs: those of the neighbour list within a thinner skin (their pattern
    // changes only when that sub-list is filtered afresh).
    candidates_.update(forces.list(), box, x, y);
    const SubList& list = candidates_;
    if (list.builds() != pairs_version_) {
        pairs_.resize(list.size());
        for (std::size_t k = 0; k < list.size(); ++k) pairs_[k] = {list.owner()[k], list.neighbor()[k]};
        pairs_version_ = list.builds();
    }
    in_contact_.resize(list.size());
    bx_.resize(n);
    by_.resize(n);
    const double inv_kd = 1.0 / kd_;
    // Contacts and the affine part of the contact drag: −γ̇ Σ_j [y_i − y_j] (k_d cancels),
    // from the force loop's record of this very evaluation when it made one (the usual case:
    // the pairs are not walked again), else from a pass over the candidates that computes
    // the same flags and sums (the same bits: the same separations and tests, the sums in
    // the same order, a non-touching pair adding r_y · 0).
    const auto recorded = forces.recorded_contacts(box, x, y);
    const double* sum_ry = nullptr;
    if (recorded && list.parent_builds() == forces.list().builds()) {
        const std::uint8_t* const parent_touching = recorded->touching.data();
        const std::uint32_t* const parent_entry = list.parent_entry().data();
        std::uint8_t* const touching_out = in_contact_.data();
        parallel_for(list.size(), [=](std::size_t k) { touching_out[k] = parent_touching[parent_entry[k]]; });
        sum_ry = recorded->sum_ry.data();
    } else {
        sum_ry_.assign(n, 0.0);
        // Raw pointers: the compiler need not reload the vectors' storage after each store.
        std::uint8_t* const touching_out = in_contact_.data();
        double* const sums = sum_ry_.data();
        for_each_pair(list, box, x, y, [=](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touches) {
            touching_out[k] = static_cast<std::uint8_t>(touches);
            const double ry_touching = r.y * static_cast<double>(touches);
            sums[i] += ry_touching;
            sums[j] -= ry_touching;
        });
        sum_ry = sum_ry_.data();
    }
    double* const bx = bx_.data();
    double* const by = by_.data();
    parallel_for(n, [=](std::size_t i) {
        bx[i] = fx[i] * inv_kd - rate * sum_ry[i];
        by[i] = fy[i] * inv_kd;
    });
    if (!solver_) solver_ = linalg::make_contact_solver(backend_, n, delta_, petsc_options_);
    last_ = solver_->solve(pairs_, in_contact_, pairs_version_, tag, bx_, by_, ux, uy);
}

double Cd0::candidate_skin(const ReplicaParams& params) { return params.skin / 3.0; }

void Cd0::prepare(System& sys, ForceField& forces, double rate) {
    Particles& p = sys.particles;
    forces.record_contacts();  // from the next evaluation on (this one may not have)
    solve(forces, sys.box, p.x, p.y, p.tag, p.fx, p.fy, rate, p.ux, p.uy);
}

void Cd0::advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t) {
    Particles& p = sys.particles;
    overdamped_step(sys, forces, dt, rate, heun_, 1.0, p.ux, p.uy, scratch_, [&](System& s) {
        // Forces and a second solve at the predicted positions, warm-started from u.
        const std::size_t n = p.size();
        fx1_.resize(n);
        fy1_.resize(n);
        ux1_.assign(p.ux.begin(), p.ux.end());
        uy1_.assign(p.uy.begin(), p.uy.end());
        forces.compute_at(s.box, p.x, p.y, p.diameter, fx1_, fy1_);
        solve(forces, s.box, p.x, p.y, p.tag, fx1_, fy1_, rate, ux1_, uy1_);
        return std::pair<std::span<const double>, std::span<const double>>{ux1_, uy1_};
    });
}

Dissipation Cd0::dissipation(const System& sys, const ForceField& /*forces*/, double rate) const {
    const Particles& p = sys.particles;
    Dissipation d;
    double vxx = 0, vyy = 0, vyx = 0;
    // The contacts of the last solve, whose positions these still are (dissipation() follows
    // prepare()): their separations computed again here, at samples, rather than stored by
    // every solve.
    const auto contact_term = [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool) {
        if (!in_contact_[k]) return;
        const double wx = p.ux[i] - p.ux[j] + rate * r.y;  // relative lab velocity
        const double wy = p.uy[i] - p.uy[j];
        d.power += kd_ * (wx * wx + wy * wy);
        const double fx = -kd_ * wx, fy = -kd_ * wy;  // on i from j
        vxx += r.x * fx;
        vyy += r.y * fy;
        vyx += r.y * fx;
    };
    for_each_pair(candidates_, sys.box, p.x, p.y, contact_term);
    d.power += kd_ * delta_ * static_cast<double>(p.size()) * mean_square_velocity(p);
    d.pressure = 0.5 * (vxx + vyy) / sys.box.area();
    d.shear_stress = -vyx / sys.box.area();
    return d;
}

void relax_cd0_start(System& sys, const ReplicaParams& p) {
    const double dt = std::min(p.dt, 0.5 * reservoir_drag_stable_dt(p));
    const auto steps = static_cast<std::int64_t>(std::ceil(kCd0StartRelaxTime * p.kd / dt));
    ForceField forces(potential::make_soft_sphere(p.alpha), p.skin);
    ReplicaParams relax;
    relax.integrator = "euler";
    relax.kd = p.kd;
    Rd0 model(relax);
    for (std::int64_t step = 0; step < steps; ++step) {
        forces.compute(sys, Tally::ForcesOnly);
        model.prepare(sys, forces, 0.0);
        model.advance(sys, forces, dt, 0.0, step);
    }
}

namespace {
constexpr std::string_view kCd0Parameters[] = {"dt", "integrator", "kd", "delta", "solver", "petsc_options"};
}

DynamicsInfo cd0_model() {
    return {.name = "CD0",
            .summary = "overdamped, contact dissipation: a contact-matrix solve per step "
                       "(thesis eqs. 4.15-4.19)",
            .parameters = kCd0Parameters,
            .evaluations_per_step = [](const ReplicaParams& p) { return p.integrator == "heun" ? 2 : 1; },
            .stable_dt = contact_drag_stable_dt,
            .make = [](const ReplicaParams& p, const RandomKey&) -> std::unique_ptr<Model> {
                return std::make_unique<Cd0>(p);
            },
            // The contact matrix and its factor: the peak over the libraries' base, from the relaxed
            // random start, is about 2.0 kB per disk at N = 65536 and 131072 (tests/bench/cd0_solver.md,
            // "CD0's start").
            .bytes_per_disk = 2560.0,
            .stable_dt_basis = contact_drag_dt_basis,
            .advisory = [](const ReplicaParams& p) { return overdamped_dt_advisory(p, contact_drag_stable_dt); },
            .relax_start = relax_cd0_start,
            .thread_scaling = ThreadScaling::contact_solve};
}

}  // namespace jamsim
