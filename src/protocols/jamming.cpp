#include "jamsim/protocols/jamming.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace jamsim {

namespace {
std::string str(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}
std::string str(std::int64_t v) { return std::to_string(v); }
} // namespace

void set_packing_fraction(System& sys, ForceField& forces, double phi) {
    const double side = box_side_for(sys.particles, phi);
    const double scale = side / sys.box.side();
    Box box(side, sys.box.strain());
    for (std::size_t i = 0; i < sys.particles.size(); ++i) {
        sys.particles.x[i] *= scale;  // sheared coordinates scale with the cell
        sys.particles.y[i] *= scale;
    }
    sys.box = box;
    forces.invalidate();
}

StaticState quench(System& sys, ForceField& forces, Minimizer& minimizer,
                   const MinimizeCriteria& criteria) {
    StaticState s;
    s.phi = packing_fraction(sys.particles, sys.box);
    s.minimum = minimizer.minimize(sys, forces, criteria);
    if (s.minimum.outcome == MinimizeOutcome::NotConverged)
        throw std::runtime_error("minimisation did not converge at phi = " + str(s.phi) +
                                 " after " + str(s.minimum.iterations) +
                                 " iterations (E/N " + str(s.minimum.energy_per_particle) +
                                 ", largest force " + str(s.minimum.max_force) +
                                 ", mean contact force " + str(s.minimum.mean_contact_force) + ")");
    s.network = contact_network(sys, forces.list());
    return s;
}

JammingPoint find_jamming_point(System& sys, ForceField& forces, Minimizer& minimizer,
                                const MinimizeCriteria& criteria, double phi_step,
                                double phi_tol) {
    JammingPoint out;
    StaticState state = quench(sys, forces, minimizer, criteria);
    ++out.minimizations;
    out.force_evaluations += state.minimum.force_evaluations;
    double phi = state.phi, step = phi_step;
    bool crossed = false;  // the threshold has been bracketed at least once
    while (!(state.jammed() && crossed && step < phi_tol)) {
        if (!state.jammed()) out.phi_unjammed = phi;
        phi += state.jammed() ? -step : step;
        if (!(phi > 0.0 && phi < 1.0))
            throw std::runtime_error("jamming search left 0 < phi < 1 (phi = " + str(phi) + ")");
        set_packing_fraction(sys, forces, phi);
        const bool was_jammed = state.jammed();
        state = quench(sys, forces, minimizer, criteria);
        ++out.minimizations;
        out.force_evaluations += state.minimum.force_evaluations;
        if (state.jammed() != was_jammed) {  // crossed the threshold: refine and reverse
            step *= 0.5;
            crossed = true;
        }
    }
    // The configuration follows its own landscape, so the answer is the final bracket: the
    // jammed state now, within `step` of the last unjammed one.
    out.phi_j = phi;
    out.state = state;
    return out;
}

} // namespace jamsim
