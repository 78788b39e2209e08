#pragma once
#include <span>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/minimize/minimizer.hpp"

namespace jamsim {

/// The coordinates a minimiser moves: x = base + offset per disk, with the base fixed while
/// the offsets stay small (rebased when they grow), so separations are resolved to ~ε|offset|
/// for every disk alike. Keeps sys.particles.x, y = base + offset current (for the neighbour
/// list and for the caller) and evaluates forces into sys.particles.fx, fy.
/// Far from convergence resolution does not matter, so a minimisation starts with plain
/// positions (cheaper: no offsets in the force loop) and splits once the largest force has
/// come down to converging_below(f̄) (split_if_converging). Without splitting
/// (criteria.split_positions = false) it stays plain throughout, for comparison.
class SplitPositions {
  public:
    SplitPositions(System& sys, ForceField& forces, bool split);

    /// Switch to base + offset (base = the current positions) once fmax is below
    /// converging_below(f̄), if splitting was asked for.
    void split_if_converging(double fmax, double mean_contact_force);
    static constexpr double kSplitBelow = 1e-6;
    /// Where a minimisation approaches the round-off regime: max(kSplitBelow × f̄,
    /// kFloorMargin × ε L k_e/d_s) with L the cell side. The second term is the force that a
    /// position error of one ulp of L makes in a contact of unit stiffness, with a margin: near
    /// φ_J, f̄ is so small that 1e-6 f̄ lies below what plain coordinates can resolve.
    double converging_below(double mean_contact_force) const;
    static constexpr double kFloorMargin = 1e3;

    std::size_t size() const { return base_x_.size(); }

    /// Move every disk by s d_i, d a lab-frame direction per disk (like the forces, so that
    /// −F·d is the slope of the energy along d at any strain): the sheared coordinates move by
    /// s (d_x − γ d_y, d_y). dmax: the largest component of d when the caller knows it (< 0:
    /// computed here).
    void move(double s, std::span<const double> dx, std::span<const double> dy, double dmax = -1.0);

    /// Forces at the current positions (into sys.particles.fx, fy), with the tallies.
    ForceResult evaluate(Tally tally = Tally::Full);

    /// Largest force component max_i max(|F_ix|, |F_iy|).
    double max_force() const;

    /// f̄ = Σ_contacts r_ij·f_ij / (N_c ⟨d⟩) from a tallied evaluation.
    double mean_contact_force(const ForceResult& f) const;

    /// Fold the offsets into the base once they have grown beyond `limit` (positions move
    /// far early in a minimisation; the base must be fixed, and the offsets small, while it
    /// converges). Positions are not wrapped, so the neighbour list stays valid.
    void rebase_if_larger(double limit = kRebaseOffset);
    static constexpr double kRebaseOffset = 1e-3;  ///< d_s

    /// Track progress near the round-off floor: returns true when the largest force, once
    /// below converging_below(f̄), has not halved for `window` calls since its last halving (a
    /// minimisation stalled at the floor). Above that the force falls by the physics (slowly,
    /// on the soft modes near jamming, for FIRE at large N over 10⁵ steps and more), so no
    /// stall is declared there; the iteration limit bounds it.
    bool stalled(double max_force, double mean_contact_force, std::int64_t window);

    std::int64_t evaluations() const { return evaluations_; }
    System& system() { return sys_; }

  private:
    System& sys_;
    ForceField& forces_;
    bool split_requested_;
    bool split_ = false;
    std::vector<double> base_x_, base_y_, off_x_, off_y_;
    double max_offset_ = 0.0;
    double best_force_ = -1.0;
    double moved_ = 0.0;  // bound on lab displacements since the list's last build
    std::size_t builds_seen_ = static_cast<std::size_t>(-1);
    std::int64_t since_best_ = 0;
    double mean_diameter_ = 1.0;
    std::int64_t evaluations_ = 0;
};

/// Fill a MinimizeResult from the last tallied evaluation.
MinimizeResult summarize(const SplitPositions& pos, const System& sys, const ForceResult& f, MinimizeOutcome outcome,
                         std::int64_t iterations);

/// The stopping rule of MinimizeCriteria for a tallied evaluation whose largest force
/// component is `max_force` (SplitPositions::max_force); NotConverged = go on.
/// What the minimiser's next evaluations must tally: energy and virial cost ~30% of an
/// evaluation and only the stopping rule needs them, so Full every 32 iterations and on
/// every one once the rule is within reach (fmax within 100× of the force tolerance, or E/N
/// of the last tallied evaluation within 1e4× of the energy floor); ForcesOnly otherwise.
Tally tally_for(std::int64_t iteration, double max_force, double mean_contact_force, const ForceResult& last_tallied,
                std::size_t disks, const MinimizeCriteria& c);

MinimizeOutcome check_stop(const SplitPositions& pos, const System& sys, const ForceResult& f,
                           const MinimizeCriteria& c, double max_force);

}  // namespace jamsim
