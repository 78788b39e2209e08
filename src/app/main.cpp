// jamsim: sheared soft disks through the jamming transition.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "jamsim/core/version.hpp"
#include "campaign_commands.hpp"
#include "minimize_command.hpp"
#include "reference_commands.hpp"
#include "replica_command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"jamsim: sheared bidisperse soft disks through the jamming transition"};
    app.set_version_flag("--version", std::string("jamsim ") + jamsim::kVersion);
    app.require_subcommand(1);
    jamsim::app::add_replica_command(app);
    jamsim::app::add_run_command(app, argc, argv);
    jamsim::app::add_status_command(app);
    jamsim::app::add_merge_command(app, argc, argv);
    jamsim::app::add_minimize_command(app);
    jamsim::app::add_parameters_command(app);
    jamsim::app::add_models_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::cerr << "jamsim: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
