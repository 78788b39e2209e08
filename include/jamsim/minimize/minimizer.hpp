#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"

namespace jamsim {

/// When a minimisation stops (thesis §4.7). Recorded with every result in files and archives.
struct MinimizeCriteria {
    /// Unjammed: the energy per particle fell below this (units k_e).
    double energy_floor = 1e-16;
    /// Force balance, relative: the largest force component max_i max(|F_ix|, |F_iy|) is at
    /// most force_tol × f̄, with f̄ = Σ_contacts r_ij·f_ij / (N_c ⟨d⟩) the mean contact force
    /// (⟨d⟩ the mean diameter). Scale-free, so it means the same at any pressure...
    double force_tol = 1e-10;
    /// ... down to an absolute floor (k_e/d_s): also stop when the largest component is at
    /// most this. A contact force k_e (1 − r/d)/d is computed from r ≈ d, whose absolute
    /// precision is ε d ≈ 2e-16 d_s, so no minimiser can balance forces much below ~1e-15
    /// k_e/d_s; near φ_J (f̄ ≲ 1e-5) the relative criterion alone would be unreachable.
    /// (Set force_tol = 0 and this to compare with codes that use an absolute tolerance.)
    double force_tol_abs = 1e-14;
    /// Give up (outcome NotConverged) after this many iterations ...
    std::int64_t max_iterations = 1'000'000;
    /// ... or when, once below max(1e-6 f̄, 1e3 ε L) (SplitPositions::converging_below), the
    /// largest force has not fallen below half its best
    /// value for this many iterations (stuck at a round-off floor above the tolerance).
    std::int64_t stall_iterations = 200'000;
    /// Equal positional resolution: positions are base + offset (thesis end of §4.7).
    bool split_positions = true;
    /// Called every kIterationsBetweenCalls iterations, for what must not wait for the end of
    /// a long minimisation (a campaign farm's messages); it never changes the minimisation.
    std::function<void()> between_iterations;
    static constexpr std::int64_t kIterationsBetweenCalls = 256;
};

enum class MinimizeOutcome { Unjammed, ForceBalanced, NotConverged };
std::string_view to_string(MinimizeOutcome outcome);

/// The state a minimisation ended in.
struct MinimizeResult {
    MinimizeOutcome outcome = MinimizeOutcome::NotConverged;
    std::int64_t iterations = 0;
    std::int64_t force_evaluations = 0;
    double energy_per_particle = 0.0;  ///< E/N, k_e
    double max_force = 0.0;            ///< largest force component, k_e/d_s
    double mean_contact_force = 0.0;   ///< f̄ of MinimizeCriteria, k_e/d_s
    double pressure = 0.0;             ///< k_e/d_s²
    double shear_stress = 0.0;         ///< σ = (1/A) dE/dγ, k_e/d_s²
    std::int64_t contacts = 0;         ///< pairs with r_ij < d_ij
};

/// A minimiser relaxes the positions at fixed box and strain to a local minimum of the
/// elastic energy. On return sys.particles holds the final positions and their forces.
class Minimizer {
  public:
    virtual ~Minimizer() = default;
    virtual std::string_view name() const = 0;
    virtual MinimizeResult minimize(System& sys, ForceField& forces, const MinimizeCriteria& criteria) = 0;
};

/// Registry: "cg" (hybrid HS/DY β), "cg-pr" (Polak–Ribière) or "fire" (FIRE 2.0); throws std::invalid_argument
/// listing the known names.
std::unique_ptr<Minimizer> make_minimizer(std::string_view name);
std::vector<std::string> minimizer_names();

}  // namespace jamsim
