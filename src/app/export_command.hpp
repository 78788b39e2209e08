#pragma once
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Register `jamsim export ARCHIVE --replica LIST -o OUTPUT [--format lammps|h5md]`: finished
/// replicas' final configurations as LAMMPS data files or H5MD files
/// (campaigns/README.md, "Exporting and importing configurations").
CLI::App* add_export_command(CLI::App& app);

}  // namespace jamsim::app
