#pragma once
// Set-up, checkpoint steps and wrap-up shared by every run function (dynamics and
// minimisation protocols).
#include <chrono>
#include <memory>
#include <utility>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

/// One replica in progress: its configuration (initial, or resumed from a checkpoint), its
/// force field, its clock and the rows so far; finish() hands the result back with the run
/// statistics.
class ReplicaRun {
  public:
    ReplicaRun(const ReplicaParams& p, const RunContext& context)
        : params_(p), context_(context),
          start_(std::chrono::steady_clock::now()), result{.series = {},
                                                           .final_state = context.resume    ? context.resume->system
                                                                          : context.initial ? *context.initial
                                                                                            : start_system(p)},
          forces(potential::make_soft_sphere(p.alpha), p.skin) {
        if (const ReplicaState* r = context.resume) {
            result.series = r->series;
            result.force_evaluations = r->force_evaluations;
            result.list_builds = r->list_builds;
            earlier_seconds_ = r->wall_seconds;
        }
    }

    System& system() { return result.final_state; }
    /// The step to start with: 0, or the checkpoint step of the resumed state.
    std::int64_t first_step() const { return context_.resume ? context_.resume->step : 0; }
    const ReplicaState* resumed() const { return context_.resume; }

    /// At a checkpoint step (step > 0, a multiple of checkpoint_steps, not the step a resumed
    /// run starts with): checkpoint(). Returns true when the caches were dropped (the caller
    /// makes a fresh model or minimiser).
    bool checkpoint_step(std::int64_t step, std::int64_t steps, const VelocityCorrelation* correlation = nullptr) {
        if (step == 0 || step % params_.checkpoint_steps != 0) return false;
        return checkpoint(step, steps, correlation);
    }

    /// Make `step` a checkpoint step (unless a resumed run starts with it): drop the kernel
    /// caches (a fresh force field), keep the state, save it if the policy says so and stop if
    /// asked to. `protocol` is a protocol's own state at this step (a φ_J search's bracket).
    bool checkpoint(std::int64_t step, std::int64_t steps, const VelocityCorrelation* correlation = nullptr,
                    std::vector<double> protocol = {}) {
        if (step == first_step() && resumed()) return false;
        result.list_builds += static_cast<std::int64_t>(forces.builds());
        forces = ForceField(potential::make_soft_sphere(params_.alpha), params_.skin);
        // The state at this step, kept (the last one is handed back with the result, so a
        // finished replica can be extended from it) and saved when the policy says so.
        auto state = std::make_shared<ReplicaState>(
            ReplicaState{.step = step,
                         .steps = steps,
                         .system = system(),
                         .series = result.series,
                         .correlation = correlation ? correlation->sums() : VelocityCorrelation::Sums{},
                         .protocol = std::move(protocol),
                         .force_evaluations = result.force_evaluations,
                         .list_builds = result.list_builds,
                         .wall_seconds = elapsed()});
        result.last_checkpoint = state;
        const CheckpointPolicy* policy = context_.checkpoints;
        if (!policy) return true;
        const bool stop = policy->stop && policy->stop();
        if (policy->save && (stop || (policy->due && policy->due()))) policy->save(*state);
        if (stop)
            throw ReplicaInterrupted("stopped at step " + std::to_string(step) + " of " + std::to_string(steps) +
                                     " (state saved)");
        return true;
    }

    ReplicaResult finish() {
        result.list_builds += static_cast<std::int64_t>(forces.builds());
        result.wall_seconds = elapsed();
        return std::move(result);
    }

  private:
    double elapsed() const {
        return earlier_seconds_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    const ReplicaParams& params_;
    const RunContext& context_;
    std::chrono::steady_clock::time_point start_;
    double earlier_seconds_ = 0.0;

  public:
    ReplicaResult result;
    ForceField forces;
};

}  // namespace jamsim
