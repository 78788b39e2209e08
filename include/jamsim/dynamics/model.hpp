#pragma once
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "jamsim/parallel/thread_scaling.hpp"
#include "jamsim/core/rng.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/params/parameters.hpp"

namespace jamsim {

/// Dissipation of the state whose forces and velocities are current.
struct Dissipation {
    double power = 0.0;                 ///< total dissipated power, k_e/τ
    double pressure = 0.0;              ///< dissipative contact-force pressure, k_e/d_s²
    double shear_stress = 0.0;          ///< −(1/A) Σ_contacts r_ij,y f^dis_ij,x (does work with the flow)
    double kinetic_energy = 0.0;        ///< ½ Σ m_i |u_i|² (massive models), k_e
    double pressure_kinetic = 0.0;      ///< (1/2A) Σ m_i |u_i|², k_e/d_s²
    double shear_stress_kinetic = 0.0;  ///< −(1/A) Σ m_i u_ix u_iy, k_e/d_s²
};

/// A dynamical model advances a System under constant shear rate. The driver calls, per step:
///   forces.compute(sys)          (elastic forces of the current state into sys.particles)
///   model.prepare(sys, forces, rate)
///   [at samples: model.store_velocities(sys), then the observables of that state]
///   model.advance(sys, forces, dt, rate)
/// so advance() may use the forces already in sys.particles.fx, fy as its first stage.
/// A model reads its parameters from the ReplicaParams it is made with (its registration
/// lists which, so that only those are recorded).
class Model {
  public:
    virtual ~Model() = default;

    /// Called after the forces of the current state are computed and before it is sampled;
    /// models that solve for velocities (CD0) do so here. Default: nothing.
    virtual void prepare(System& /*sys*/, ForceField& /*forces*/, double /*rate*/) {}

    /// Advance positions and γ by one step of length dt (time unit τ = k_d d_s² / k_e)
    /// at shear rate `rate` (1/τ). `step` is the index of the step (0, 1, ...): models with
    /// noise key their random numbers by it, so a run is the same however it is scheduled.
    virtual void advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t step) = 0;

    /// Make particles.ux, uy hold the non-affine velocity u = v − γ̇ y x̂ of the current state
    /// (called at samples, after prepare(); models that carry or solve for u have it already).
    virtual void store_velocities(System& /*sys*/) const {}

    /// Dissipated power and the stress of dissipative *contact* forces (zero for drag
    /// against the reservoir, which is a one-body force), for the state after prepare() and
    /// store_velocities().
    virtual Dissipation dissipation(const System& sys, const ForceField& forces, double rate) const = 0;

    /// Krylov iterations per solve in the last prepare() (CD0 with PETSc; 0 otherwise).
    virtual double solver_iterations() const { return 0.0; }

    /// True when advance() leaves sys.particles.fx, fy holding the elastic forces of the new
    /// state (it evaluated them itself), so the driver may skip its own evaluation on steps
    /// that need no energy or stress tally.
    virtual bool leaves_forces_current() const { return false; }
};

/// Mean square non-affine velocity (1/N) Σ |u_i|² of particles.ux, uy, (d_s/τ)².
double mean_square_velocity(const Particles& p);

/// What the run layer needs to know of a dynamical model: its registration. Each model's
/// file defines one (a function returning it); src/run/model_registry.cpp lists them.
struct DynamicsInfo {
    std::string_view name;     ///< as written in campaigns ("RD0")
    std::string_view summary;  ///< one line for --help and the README
    /// Parameters it reads besides the common ones (N, phi, rate, seed, run length and
    /// sampling, alpha, size_ratio, skin): recorded for its replicas, refused for others.
    std::span<const std::string_view> parameters;
    /// Force evaluations per step.
    int (*evaluations_per_step)(const ReplicaParams& p);
    /// Largest stable Δt for these parameters (+∞ when the model sets no limit).
    double (*stable_dt)(const ReplicaParams& p);
    /// The model for a replica; `key` keys its random numbers (models with noise).
    std::unique_ptr<Model> (*make)(const ReplicaParams& p, const RandomKey& key);
    /// Memory a replica needs per disk (bytes; measured peak RSS over the libraries' base at
    /// N = 65536, with a margin): the memory check before a campaign runs.
    double bytes_per_disk = 256.0;
    /// What the stable Δt rests on, for the refusal ("for RD0 with kd 1 and alpha 2 (...)");
    /// nullptr: "for MODEL with mass M and kd K (stability of the integrator)".
    std::string (*stable_dt_basis)(const ReplicaParams& p) = nullptr;
    /// A note for the run log where a limit is only advisory ("" when none); nullptr: none.
    std::string (*advisory)(const ReplicaParams& p) = nullptr;
    /// The model's start protocol, applied to the random positions of a replica that starts
    /// from them (not to an initial configuration, a resumed or an extended state); nullptr:
    /// none. Deterministic and the same bits on any thread count (start_system).
    void (*relax_start)(System& sys, const ReplicaParams& p) = nullptr;
    /// How its kernel gains from threads: the most threads the scheduler lends it.
    ThreadScaling thread_scaling = ThreadScaling::pair_loop;
};

inline double no_dt_limit(const ReplicaParams&) { return std::numeric_limits<double>::infinity(); }

}  // namespace jamsim
