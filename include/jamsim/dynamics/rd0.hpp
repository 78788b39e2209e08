#pragma once
#include <vector>

#include "jamsim/dynamics/model.hpp"
#include "jamsim/dynamics/overdamped_step.hpp"

namespace jamsim {

/// RD0: Durian's overdamped bubble model with reservoir dissipation (thesis §4.5.2,
/// eq. 4.22 with z = 1): each disk moves with the affine shear flow plus u_i = f_i^el / k_d.
/// In sheared coordinates ẋ_i = (f_ix − γ f_iy)/k_d, ẏ_i = f_iy / k_d, and γ̇ is constant.
/// Forward Euler (one force evaluation per step) or Heun (two; second order in Δt).
class Rd0 final : public Model {
  public:
    explicit Rd0(const ReplicaParams& params) : kd_(params.kd), heun_(params.integrator == "heun") {}
    void advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t step) override;
    /// P = k_d Σ |u_i|² (drag against the reservoir); no contact stress.
    Dissipation dissipation(const System& sys, const ForceField& forces, double rate) const override;
    void store_velocities(System& sys) const override;

  private:
    double kd_;
    bool heun_;
    OverdampedScratch scratch_;
    std::vector<double> fx1_, fy1_;  // Heun: forces at the predicted positions, shape [N]
};

/// Registration (src/run/model_registry.cpp).
DynamicsInfo rd0_model();

}  // namespace jamsim
