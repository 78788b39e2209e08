#pragma once
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// `jamsim parameters [--markdown]`: every parameter of the table (key, campaign file,
/// option, units, default, allowed values, which models read it).
CLI::App* add_parameters_command(CLI::App& app);
/// `jamsim models`: every registered model and protocol with what it reads.
CLI::App* add_models_command(CLI::App& app);

}  // namespace jamsim::app
