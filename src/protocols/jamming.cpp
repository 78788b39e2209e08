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
}  // namespace

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

StaticState quench(System& sys, ForceField& forces, Minimizer& minimizer, const MinimizeCriteria& criteria) {
    StaticState s;
    s.phi = packing_fraction(sys.particles, sys.box);
    s.minimum = minimizer.minimize(sys, forces, criteria);
    if (s.minimum.outcome == MinimizeOutcome::NotConverged)
        throw std::runtime_error("minimisation did not converge at phi = " + str(s.phi) + " after " +
                                 str(s.minimum.iterations) + " iterations (E/N " + str(s.minimum.energy_per_particle) +
                                 ", largest force " + str(s.minimum.max_force) + ", mean contact force " +
                                 str(s.minimum.mean_contact_force) + ")");
    s.network = contact_network(sys, forces.list());
    return s;
}

std::vector<double> JammingSearch::pack() const {
    return {phi,
            step,
            crossed ? 1.0 : 0.0,
            jammed ? 1.0 : 0.0,
            phi_unjammed,
            static_cast<double>(minimizations),
            static_cast<double>(force_evaluations)};
}

JammingSearch JammingSearch::unpack(const std::vector<double>& v) {
    if (v.size() != 7)
        throw std::invalid_argument("a jamming search state has 7 numbers, not " + std::to_string(v.size()));
    return {.phi = v[0],
            .step = v[1],
            .crossed = v[2] != 0.0,
            .jammed = v[3] != 0.0,
            .phi_unjammed = v[4],
            .minimizations = static_cast<int>(v[5]),
            .force_evaluations = static_cast<std::int64_t>(v[6])};
}

JammingPoint find_jamming_point(System& sys, ForceField& forces, Minimizer& minimizer, const MinimizeCriteria& criteria,
                                double phi_step, double phi_tol, const JammingSearch* resume,
                                const std::function<void(const JammingSearch&)>& before_minimisation) {
    JammingSearch s;
    StaticState state;
    const auto minimise = [&] {
        state = quench(sys, forces, minimizer, criteria);
        ++s.minimizations;
        s.force_evaluations += state.minimum.force_evaluations;
    };
    bool pending = false;  // a resumed search starts with the minimisation it was saved before
    if (resume) {
        s = *resume;
        pending = true;
    } else {
        minimise();
        s.phi = state.phi;
        s.step = phi_step;
        s.jammed = state.jammed();
    }
    for (;;) {
        if (!pending) {
            if (s.jammed && s.crossed && s.step < phi_tol) break;
            if (!s.jammed) s.phi_unjammed = s.phi;
            const double before = s.phi;
            s.phi += s.jammed ? -s.step : s.step;
            // A step below phi's resolution would repeat the same minimisation for ever
            // (phi_tol >= 1e-14 keeps the steps above it).
            if (s.phi == before)
                throw std::runtime_error("jamming search: a step of " + str(s.step) + " leaves phi = " + str(before) +
                                         " unchanged (raise phi_tol)");
            if (!(s.phi > 0.0 && s.phi < 1.0))
                throw std::runtime_error("jamming search left 0 < phi < 1 (phi = " + str(s.phi) + ")");
            set_packing_fraction(sys, forces, s.phi);
            if (before_minimisation) before_minimisation(s);
        }
        pending = false;
        const bool was_jammed = s.jammed;
        minimise();
        s.jammed = state.jammed();
        if (s.jammed != was_jammed) {  // crossed the threshold: refine and reverse
            s.step *= 0.5;
            s.crossed = true;
        }
    }
    // The configuration follows its own landscape, so the answer is the final bracket: the
    // jammed state now, within `step` of the last unjammed one.
    return {.phi_j = s.phi,
            .phi_unjammed = s.phi_unjammed,
            .state = state,
            .minimizations = s.minimizations,
            .force_evaluations = s.force_evaluations};
}

}  // namespace jamsim
