#pragma once
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/dynamics/force_field.hpp"

namespace jamsim {

/// Dissipation of the state whose forces and velocities are current.
struct Dissipation {
    double power = 0.0;         ///< total dissipated power, k_e/τ
    double pressure = 0.0;      ///< dissipative contact-force pressure, k_e/d_s²
    double shear_stress = 0.0;  ///< −(1/A) Σ_contacts r_ij,y f^dis_ij,x (does work with the flow)
    double kinetic_energy = 0.0;        ///< ½ Σ m_i |u_i|² (massive models), k_e
    double pressure_kinetic = 0.0;      ///< (1/2A) Σ m_i |u_i|², k_e/d_s²
    double shear_stress_kinetic = 0.0;  ///< −(1/A) Σ m_i u_ix u_iy, k_e/d_s²
};

/// Time integration scheme for first-order (overdamped) models.
enum class Integrator { Euler, Heun };

/// Parameters every dynamical model may read. Units: k_e = k_d = d_s = 1 unless changed.
struct ModelParams {
    double kd = 1.0;                          ///< dissipation coefficient k_d
    Integrator integrator = Integrator::Euler;
    double delta = 1e-3;                      ///< CD0 substrate drag δ = k_0/k_d
    std::string petsc_options = "";           ///< CD0: extra PETSc options (prefix cd0_)
    std::string solver = "auto";              ///< CD0 backend: "auto", "petsc" (KSP) or "eigen" (LDLT)
    double mass = 1.0;                        ///< massive models: mass of a small disk
};

/// A dynamical model advances a System under constant shear rate. The driver calls, per step:
///   forces.compute(sys)          (elastic forces of the current state into sys.particles)
///   model.prepare(sys, forces, rate)
///   [observables of that state]
///   model.advance(sys, forces, dt, rate)
/// so advance() may use the forces already in sys.particles.fx, fy as its first stage.
class Model {
  public:
    virtual ~Model() = default;
    virtual std::string_view name() const = 0;

    /// Called after the forces of the current state are computed and before it is sampled;
    /// models that solve for velocities (CD0) do so here. Default: nothing.
    virtual void prepare(System& /*sys*/, ForceField& /*forces*/, double /*rate*/) {}

    /// Advance positions and γ by one step of length dt (time unit τ = k_d d_s² / k_e)
    /// at shear rate `rate` (1/τ).
    virtual void advance(System& sys, ForceField& forces, double dt, double rate) = 0;

    /// Mean square non-affine velocity (1/N) Σ |u_i|², u = v − γ̇ y x̂, of the state whose
    /// forces are in sys.particles (units (d_s/τ)²).
    virtual double nonaffine_velocity_sq(const System& sys) const = 0;

    /// Dissipated power and the stress of dissipative *contact* forces (zero for drag
    /// against the reservoir, which is a one-body force), for the state after prepare().
    virtual Dissipation dissipation(const System& sys, const ForceField& forces,
                                    double rate) const = 0;

    /// Make particles.ux, uy hold the non-affine velocity of the current state (called only
    /// at samples; models that solve for u have it already).
    virtual void store_velocities(System& /*sys*/) const {}

    /// Krylov iterations per solve in the last prepare() (CD0 with PETSc; 0 otherwise).
    virtual double solver_iterations() const { return 0.0; }

    /// True when advance() leaves sys.particles.fx, fy holding the elastic forces of the new
    /// state (it evaluated them itself), so the driver may skip its own evaluation on steps
    /// that need no energy or stress tally.
    virtual bool leaves_forces_current() const { return false; }
};

/// Registry: a model by name ("RD0"); throws std::invalid_argument listing the known names.
std::unique_ptr<Model> make_model(std::string_view name, const ModelParams& params);

/// Names accepted by make_model.
std::vector<std::string> model_names();

} // namespace jamsim
