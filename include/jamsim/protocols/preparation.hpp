#pragma once
// How a configuration is prepared before it is quenched or compressed (Paper I): thermal
// cooling and quasistatic shear. Both act on the system in place.
#include <cstdint>
#include <functional>

#include "jamsim/core/rng.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/minimize/minimizer.hpp"

namespace jamsim {

/// Called before step `step` of a long protocol (not before its first one), with the force
/// evaluations of the steps taken so far in this call: where a run may checkpoint, drop the
/// force field's caches (it may reassign `forces`) or stop by throwing.
using BeforeStep = std::function<void(std::int64_t step, std::int64_t evaluations)>;

/// A linear cooling schedule T(t) = T₀ (1 − t / duration) for overdamped Langevin dynamics.
struct CoolingSchedule {
    double temperature = 1e-3;  ///< T₀, k_e
    double duration = 1e4;      ///< time over which T falls to 0, τ
    double dt = 0.1;            ///< time step, τ
    double kd = 1.0;            ///< dissipation coefficient k_d
};

/// Overdamped Langevin dynamics at fixed box and strain (RD0 with noise):
///   x += (f/k_d) Δt + sqrt(2 T(t) Δt / k_d) ξ,
/// ξ a unit Gaussian per disk and step from `noise`, keyed by (disk tag, step), so the result
/// does not depend on the order of the disks in memory. Starts at step `first_step` (0, or
/// the step a checkpoint was saved before) and calls `before` before every later step.
/// Returns the force evaluations (one per step taken).
std::int64_t cool(System& sys, ForceField& forces, const CoolingSchedule& schedule, const RngStream& noise,
                  std::int64_t first_step = 0, const BeforeStep& before = {});
/// Steps of a cooling schedule: ceil(duration / dt).
std::int64_t cooling_steps(const CoolingSchedule& schedule);

/// Quasistatic shear to `strain` in steps of `strain_step`: minimise, then γ → γ + Δγ
/// (affine, through the Lees–Edwards box), repeated; the last strain step is not minimised.
/// Starts at step `first_step` and calls `before` before every later step, as cool() does.
/// Returns the force evaluations; a minimisation that does not converge throws.
std::int64_t shear_quasistatically(System& sys, ForceField& forces, Minimizer& minimizer,
                                   const MinimizeCriteria& criteria, double strain, double strain_step,
                                   std::int64_t first_step = 0, const BeforeStep& before = {});
/// Steps of a quasistatic shear: ceil(strain / strain_step).
std::int64_t shear_steps(double strain, double strain_step);

}  // namespace jamsim
