#include "jamsim/minimize/split_positions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/parallel/reduce.hpp"

namespace jamsim {

SplitPositions::SplitPositions(System& sys, ForceField& forces, bool split)
    : sys_(sys), forces_(forces), split_requested_(split) {
    Particles& p = sys.particles;
    // Start inside the cell; a disk that had to be wrapped invalidates the list's image shifts.
    bool wrapped = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x0 = p.x[i], y0 = p.y[i];
        sys.box.wrap_into_cell(p.x[i], p.y[i]);
        wrapped = wrapped || p.x[i] != x0 || p.y[i] != y0;
    }
    // Disks in cell order (as the dynamics keep them), so the force loop's gathers and
    // scatters stay local; outputs are by tag, so the order is invisible.
    if (wrapped || forces.builds() == 0) {
        p.permute(spatial_order(p, sys.box, max_diameter(p) + forces.list().skin()));
        forces.invalidate();
    }
    base_x_.assign(p.x.begin(), p.x.end());
    base_y_.assign(p.y.begin(), p.y.end());
    off_x_.assign(p.size(), 0.0);
    off_y_.assign(p.size(), 0.0);
    double sum = 0;
    for (double d : p.diameter) sum += d;
    mean_diameter_ = p.size() ? sum / static_cast<double>(p.size()) : 1.0;
}

void SplitPositions::move(double s, std::span<const double> dx, std::span<const double> dy, double dmax) {
    Particles& p = sys_.particles;
    const std::size_t n = size();
    // d is a lab-frame displacement (forces are lab-frame, so −F·d is the slope of the energy
    // along it); the sheared coordinates move by M(γ)⁻¹ d = (d_x − γ d_y, d_y).
    const double gamma = sys_.box.strain();
    if (split_) {
        // One pass: the move and the largest offset (a maximum: any split, the same value).
        const double largest = blocked_reduce<double>(
            n,
            [&](std::size_t lo, std::size_t hi) {
                double m[4] = {0, 0, 0, 0};  // four lanes: no long dependency chain
                for (std::size_t i = lo; i < hi; ++i) {
                    off_x_[i] += s * (dx[i] - gamma * dy[i]);
                    off_y_[i] += s * dy[i];
                    p.x[i] = base_x_[i] + off_x_[i];
                    p.y[i] = base_y_[i] + off_y_[i];
                    m[i & 3] = std::max(m[i & 3], std::max(std::abs(off_x_[i]), std::abs(off_y_[i])));
                }
                return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
            },
            [](double a, double b) { return std::max(a, b); });
        max_offset_ = std::max(max_offset_, largest);
    } else {
        parallel_for(n, [&](std::size_t i) {
            p.x[i] += s * (dx[i] - gamma * dy[i]);
            p.y[i] += s * dy[i];
        });
    }
    if (dmax < 0.0) dmax = parallel_max(n, [&](std::size_t i) { return std::max(std::abs(dx[i]), std::abs(dy[i])); });
    // The lab displacement of disk i is s d_i: at most sqrt(2) |s| times the largest
    // component, with 1e-12 relative slack for the rounding of the sheared update.
    if (forces_.builds() != builds_seen_) {
        builds_seen_ = forces_.builds();
        moved_ = 0.0;
    }
    moved_ += std::abs(s) * dmax * std::numbers::sqrt2 * (1 + 1e-12);
}

ForceResult SplitPositions::evaluate(Tally tally) {
    Particles& p = sys_.particles;
    ++evaluations_;
    if (!split_) return forces_.compute_at(sys_.box, p.x, p.y, p.diameter, p.fx, p.fy, tally);
    // The bound is only known for moves since the build this object has seen.
    const double bound = forces_.builds() == builds_seen_ ? moved_ : -1.0;
    const ForceResult f = forces_.compute_split(sys_.box, p.x, p.y, base_x_, base_y_, off_x_, off_y_, p.diameter, p.fx,
                                                p.fy, tally, bound);
    if (forces_.builds() != builds_seen_) {  // rebuilt now: displacements count from here
        builds_seen_ = forces_.builds();
        moved_ = 0.0;
    }
    return f;
}

double SplitPositions::max_force() const {
    const Particles& p = sys_.particles;
    return parallel_max(p.size(), [&](std::size_t i) { return std::max(std::abs(p.fx[i]), std::abs(p.fy[i])); });
}

double SplitPositions::mean_contact_force(const ForceResult& f) const {
    if (f.contacts == 0) return 0.0;
    return (f.virial_xx + f.virial_yy) / (static_cast<double>(f.contacts) * mean_diameter_);
}

void SplitPositions::rebase_if_larger(double limit) {
    if (!split_ || max_offset_ <= limit) return;
    Particles& p = sys_.particles;
    parallel_for(size(), [&](std::size_t i) {
        base_x_[i] = p.x[i];
        base_y_[i] = p.y[i];
        off_x_[i] = off_y_[i] = 0.0;
    });
    max_offset_ = 0.0;
}

void SplitPositions::split_if_converging(double fmax, double mean_contact_force) {
    if (split_ || !split_requested_ || fmax > converging_below(mean_contact_force)) return;
    split_ = true;
    const Particles& p = sys_.particles;
    std::copy(p.x.begin(), p.x.end(), base_x_.begin());
    std::copy(p.y.begin(), p.y.end(), base_y_.begin());
    std::fill(off_x_.begin(), off_x_.end(), 0.0);
    std::fill(off_y_.begin(), off_y_.end(), 0.0);
    max_offset_ = 0.0;
}

double SplitPositions::converging_below(double mean_contact_force) const {
    return std::max(kSplitBelow * mean_contact_force,
                    kFloorMargin * std::numeric_limits<double>::epsilon() * sys_.box.side());
}

bool SplitPositions::stalled(double max_force, double mean_contact_force, std::int64_t window) {
    if (max_force > converging_below(mean_contact_force)) {  // far above the floor
        best_force_ = -1.0;
        return false;
    }
    if (best_force_ < 0.0 || max_force < 0.5 * best_force_) {
        best_force_ = max_force;
        since_best_ = 0;
        return false;
    }
    return ++since_best_ > window;
}

MinimizeResult summarize(const SplitPositions& pos, const System& sys, const ForceResult& f, MinimizeOutcome outcome,
                         std::int64_t iterations) {
    MinimizeResult r;
    r.outcome = outcome;
    r.iterations = iterations;
    r.force_evaluations = pos.evaluations();
    r.energy_per_particle = f.energy / static_cast<double>(sys.particles.size());
    r.max_force = pos.max_force();
    r.mean_contact_force = pos.mean_contact_force(f);
    r.pressure = f.pressure(sys.box);
    r.shear_stress = f.shear_stress(sys.box);
    r.contacts = f.contacts;
    return r;
}

Tally tally_for(std::int64_t iteration, double max_force, double mean_contact_force, const ForceResult& last_tallied,
                std::size_t disks, const MinimizeCriteria& c) {
    const bool near = max_force <= 100.0 * std::max(c.force_tol_abs, c.force_tol * mean_contact_force) ||
                      last_tallied.energy / static_cast<double>(disks) < 1e4 * c.energy_floor;
    return near || iteration % 32 == 31 ? Tally::Full : Tally::ForcesOnly;
}

MinimizeOutcome check_stop(const SplitPositions& pos, const System& sys, const ForceResult& f,
                           const MinimizeCriteria& c, double fmax) {
    if (f.energy / static_cast<double>(sys.particles.size()) < c.energy_floor) return MinimizeOutcome::Unjammed;
    if (fmax <= c.force_tol * pos.mean_contact_force(f) || fmax <= c.force_tol_abs)
        return MinimizeOutcome::ForceBalanced;
    return MinimizeOutcome::NotConverged;
}

}  // namespace jamsim
