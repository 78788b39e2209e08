#pragma once
// `jamsim plan CAMPAIGN --nodes 1,4,16,64 --cores-per-node 64 --threads 1,4`: the farm's
// scheduler run as a discrete-event simulation (campaign/scheduler.hpp) on the dry run's
// per-replica costs (probed here, or read from a saved dry run with --costs), one table row
// per node count and threads: makespan, its lower bound, the critical path, cores left idle.
#include <CLI/CLI.hpp>

namespace jamsim::app {

CLI::App* add_plan_command(CLI::App& app, int& argc, char**& argv);

}  // namespace jamsim::app
