// jamsim: sheared soft disks through the jamming transition.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <exception>
#include <filesystem>
#include <iostream>
#include <regex>
#include <sstream>
#include <thread>
#include <chrono>
#include <string>
#include <csignal>
#include <string_view>

#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/io/read_deadline.hpp"
#include "jamsim/core/version.hpp"
#include "campaign_commands.hpp"
#include "exit_status.hpp"
#include "option_checks.hpp"
#include "export_command.hpp"
#include "minimize_command.hpp"
#include "plan_command.hpp"
#include "reference_commands.hpp"
#include "replica_command.hpp"
#include "threads_option.hpp"

namespace jamsim::app {

/// The exit status of a parse error, its message printed as CLI11 prints it: a command's own
/// status (CLI::RuntimeError: 75 interrupted, 2 refused, 1 failed) as it is, --help and
/// --version 0, and every usage error (CLI11's 100-127: an unknown option, a missing or
/// malformed value, a refused value) 2, the status of a usage error by convention.
int exit_status(const CLI::App& app, const CLI::ParseError& e) {
    // Under mpirun every rank meets the same usage error: rank 0 alone says it, and the others
    // end after it (the launcher kills the rest of the job when the first rank ends).
    std::ostringstream unsaid;
    const bool other_rank = launcher_ranks().second > 0;
    const int status = other_rank ? app.exit(e, unsaid, unsaid) : app.exit(e);
    if (other_rank && status != 0) std::this_thread::sleep_for(std::chrono::seconds(2));
    if (e.get_name() == "RuntimeError" || status == 0) return status;
    return status >= static_cast<int>(CLI::ExitCodes::IncorrectConstruction) ? app::kExitRefused : status;
}

/// CLI11's own wording of two usage errors in jamsim's ("--output: At Most 1 required but
/// received 2", "--progress: bogus not in {auto,lines,redraw}"); other text as it is.
std::string in_jamsim_words(const std::string& text) {
    static const std::regex repeated(R"(^(--[A-Za-z0-9-]+): At Most 1 required but received ([0-9]+)$)");
    static const std::regex not_member(R"(^(--[A-Za-z0-9-]+): (.*) not in \{(.*)\}$)");
    std::smatch m;
    if (std::regex_match(text, m, repeated)) return m[1].str() + " is given " + m[2].str() + " times: give it once";
    if (std::regex_match(text, m, not_member)) {
        std::string choices = m[3].str();
        for (std::size_t comma = choices.find(','); comma != std::string::npos; comma = choices.find(',', comma + 2))
            choices.replace(comma, 1, ", ");
        return m[1].str() + " = " + m[2].str() + " is not allowed: one of " + choices;
    }
    return text;
}

/// "" unless TMPDIR names something other than a writable folder for a command that starts MPI
/// (Open MPI keeps its session files there: a file there ended the run in Open MPI's words, "A
/// call to mkdir was unable to create the desired directory").
std::string temporary_folder_problem(int argc, char** argv) {
    if (argc < 2) return "";
    const std::string_view command = argv[1];
    if (command != "run" && command != "status" && command != "merge" && command != "plan") return "";
    const char* folder = std::getenv("TMPDIR");
    if (!folder || !*folder) return "";
    std::error_code ec;
    if (std::filesystem::is_directory(folder, ec) && ::access(folder, W_OK | X_OK) == 0) return "";
    return std::string("TMPDIR = '") + folder +
           "' is not allowed: a writable folder (MPI keeps its session files there; unset, it is /tmp)";
}

/// "" when the first argument is an option or one of the commands; else one message naming it
/// and the commands (CLI11 says only "A subcommand is required").
std::string unknown_command(const CLI::App& app, int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') return "";
    std::string names;
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
        if (command->check_name(argv[1])) return "";
        names += (names.empty() ? "" : ", ") + command->get_name();
    }
    return std::string("jamsim: '") + argv[1] + "' is not a command: one of " + names +
           " (jamsim --help says what each does)";
}

}  // namespace jamsim::app

namespace {
/// `jamsim merge` takes the first stop signal as a request to stop before its next replica (a
/// second ends it at once); `jamsim run` takes a stop signal as a request to stop with its state saved (exit 75, which
/// a batch script requeues) from before the shared libraries' initialisers and MPI's start
/// (together about 0.1 s) on; a signal before the command's own code ran ended the process
/// with 143. Only the dynamic loader's mapping of the libraries (PETSc and its solvers are
/// about 100) comes before.
void stop_signals_early(int argc, char** argv, char**) {
    if (argc >= 2 && std::string_view(argv[1]) == "merge") {  // stops between two replicas
        jamsim::StopRequest::install(/*second_ends=*/true);
        return;
    }
    if (argc < 2 || std::string_view(argv[1]) != "run") return;
    for (int k = 2; k < argc; ++k)
        if (std::string_view(argv[k]) == "--dry-run") {  // it saves nothing: Ctrl-C ends it
            std::signal(SIGPIPE, SIG_IGN);               // as a run's: `| head` leaves it to finish quietly
            return;
        }
    jamsim::StopRequest::install();
}
[[gnu::section(".preinit_array"), gnu::used]] void (*const stop_signals_at_start)(int, char**,
                                                                                  char**) = &stop_signals_early;
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jamsim: sheared bidisperse soft disks through the jamming transition"};
    app.set_version_flag("--version", std::string("jamsim ") + jamsim::kVersion);
    app.require_subcommand(1);
    // CLI11's own messages ("--strain: At Most 1 required but received 2", "archive is
    // required") named no command: prefixed as jamsim's own refusals are.
    app.failure_message([](const CLI::App* root, const CLI::Error& e) {
        std::string text = jamsim::app::in_jamsim_words(e.what());
        const auto used = root->get_subcommands();
        const std::string command = used.empty() ? "jamsim" : "jamsim " + used.front()->get_name();
        if (!text.starts_with("jamsim")) text = command + ": " + text;
        return text + "\nRun '" + command + " --help' for more information.\n";
    });
    jamsim::app::add_replica_command(app);
    jamsim::app::add_run_command(app, argc, argv);
    jamsim::app::add_status_command(app);
    jamsim::app::add_merge_command(app, argc, argv);
    jamsim::app::add_plan_command(app, argc, argv);
    jamsim::app::add_export_command(app);
    jamsim::app::add_minimize_command(app);
    jamsim::app::add_parameters_command(app);
    jamsim::app::add_models_command(app);
    (void)jamsim::app::threads_from_environment();  // refused by the commands that run the kernel
    if (const std::string problem = jamsim::app::temporary_folder_problem(argc, argv); !problem.empty()) {
        std::cerr << "jamsim: " << problem << '\n';
        return jamsim::app::kExitRefused;
    }
    if (const std::string problem = jamsim::deadline_environment_problem(); !problem.empty()) {
        std::cerr << "jamsim: " << problem << '\n';
        return jamsim::app::kExitRefused;
    }
    // --version prints the version and ends: anything beside it was ignored without a word.
    if (argc > 2 && std::string_view(argv[1]) == "--version") {
        std::cerr << "jamsim: '" << argv[2] << "' is not allowed after --version: it takes nothing else\n";
        return jamsim::app::kExitRefused;
    }
    if (const std::string unknown = jamsim::app::unknown_command(app, argc, argv); !unknown.empty()) {
        std::cerr << unknown << '\n';
        return jamsim::app::kExitRefused;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) { return jamsim::app::exit_status(app, e); } catch (const std::exception& e) {
        std::cerr << "jamsim: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
