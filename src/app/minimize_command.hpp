#pragma once
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Register `jamsim minimize ...`: one RAND configuration minimised, with its cost printed on a
/// RESULT line (and optionally the start configuration written as a LAMMPS data file).
CLI::App* add_minimize_command(CLI::App& app);

}  // namespace jamsim::app
