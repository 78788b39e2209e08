#pragma once
// Set-up and wrap-up shared by every run function (dynamics and minimisation protocols).
#include <chrono>
#include <utility>

#include "jamsim/force/force_field.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

/// One replica in progress: its initial configuration, its force field, its clock and the
/// rows so far; finish() hands the result back with the run statistics.
class ReplicaRun {
  public:
    explicit ReplicaRun(const ReplicaParams& p)
        : start_(std::chrono::steady_clock::now()),
          result{.series = {}, .final_state = initial_system(p)},
          forces(potential::make_soft_sphere(p.alpha), p.skin) {}

    System& system() { return result.final_state; }

    ReplicaResult finish() {
        result.list_builds = static_cast<std::int64_t>(forces.list().builds());
        result.wall_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        return std::move(result);
    }

  private:
    std::chrono::steady_clock::time_point start_;

  public:
    ReplicaResult result;
    ForceField forces;
};

} // namespace jamsim
