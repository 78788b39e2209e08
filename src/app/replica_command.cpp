#include "replica_command.hpp"
#include "option_checks.hpp"
#include "threads_option.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "jamsim/core/parse_number.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/capacity.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/run/replica.hpp"
#include "jamsim/io/initial_states.hpp"
#include "jamsim/io/replica_file.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim::app {

namespace {

struct ReplicaOptions {
    std::map<std::string, std::string> given;  ///< parameter key -> text from the command line
    std::string output;
};

/// One message naming the option, the value and what is allowed; exit code 2.
[[noreturn]] void usage_error(const std::string& key, const std::string& value, const std::string& allowed) {
    throw CLI::ValidationError("jamsim replica: --" + key + " = " + value + " is not allowed: " + allowed);
}

/// The output: a file in a writable directory, and when it exists an earlier replica file
/// (replaced by this run, as a rerun expects), never a campaign archive, another kind of file
/// or the replica's own --initial, which the run would destroy.
void check_output_path(const std::string& path, const std::string& initial) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    std::error_code ec;
    if (const std::string why = writable_new_file(path); !why.empty()) usage_error("output", path, why);
    if (!fs::exists(p, ec)) return;
    if (!initial.empty() && fs::equivalent(p, fs::path(initial), ec))
        usage_error("output", path, "another file than --initial, which it would overwrite");
    if (!is_single_replica_file(path))
        usage_error("output", path,
                    "a new file or an earlier jamsim replica file: '" + path +
                        "' exists and is not one (a campaign archive, or another file), so it is not overwritten");
}

/// The parameters from the command line: defaults, then each given option, checked against
/// the parameter table and the model's registration.
ReplicaParams params_of(const ReplicaOptions& opt) {
    ReplicaParams params;
    for (const auto& [key, text] : opt.given) {
        const ParamInfo& info = *find_parameter(key);
        ParamValue value;
        if (!parse_value(info, text, value) || !set_value(params, info, value))
            usage_error(std::string(info.flag.substr(2)), text,
                        std::holds_alternative<double ReplicaParams::*>(info.field) && decimal_beyond_double(text)
                            ? kDoubleRangeWords
                            : value_kind(info));
    }
    for (const auto& e : validate(params)) {
        const ParamInfo* info = find_parameter(e.key);
        usage_error(info ? std::string(info->flag.substr(2)) : e.key, e.value, e.allowed);
    }
    // A parameter the model does not use would be silently ignored: refuse it.
    // (--initial and --initial-match are used by every model, once --initial names a file.)
    for (const auto& [key, text] : opt.given) {
        if (key == "initial" && text.empty())
            usage_error("initial", "''", "the path of an archive or a LAMMPS data file to start from");
        if (key == "initial_match" && params.initial.empty())
            usage_error("initial-match", text, "only with --initial (it says how to match that file's states)");
        if (!uses_parameter(params, key)) {
            // The run length follows the rate, not the model: say so (as a campaign does).
            const ModelInfo* model = find_model(params.model);
            if (model && model->kind == ModelKind::Dynamics && (key == "time" || key == "strain"))
                usage_error(key, text,
                            key == "time" ? "--time only at --rate 0 (dynamics without shear); at rate = " +
                                                show_value(params.rate) + " the run length is --strain"
                                          : "--strain only at --rate > 0; at rate 0 the run length is --time");
            usage_error(std::string(find_parameter(key)->flag.substr(2)), text, "not used by model " + params.model);
        }
    }
    // A checkpoint interval the replica never reaches never checkpoints (as a campaign refuses it).
    if (const auto given = opt.given.find("checkpoint_steps"); given != opt.given.end() &&
                                                               uses_parameter(params, "checkpoint_steps") &&
                                                               params.checkpoint_steps > checkpointed_steps(params))
        usage_error("checkpoint-steps", given->second,
                    "at most the replica's " + std::to_string(checkpointed_steps(params)) +
                        " steps (a longer interval never checkpoints)");
    // Memory, as jamsim run checks a campaign's: a large N or a dilute box (the cell grid)
    // would otherwise run into std::bad_alloc, or the node's out-of-memory killer.
    if (const std::string too_large = check_replica_memory(params); !too_large.empty())
        throw CLI::ValidationError("jamsim replica: " + too_large);
    return params;
}

void run(const ReplicaOptions& opt) {
    const ReplicaParams params = params_of(opt);
    check_output_path(opt.output, params.initial);
    if (const std::string no_room = check_replica_disk(params, opt.output); !no_room.empty())
        throw CLI::ValidationError("jamsim replica: " + no_room);
    const linalg::PetscScope petsc;  // CD0 initialises PETSc on first use; finalise it here
    // CD0 solver options from PETSc's own sources, which the file would not record.
    if (uses_parameter(params, "petsc_options"))
        if (const std::string why = linalg::petsc_environment_problem(); !why.empty())
            throw CLI::ValidationError("jamsim replica: " + why);
    // PETSc options that PETSc does not recognise or the CD0 solver does not use.
    if (!params.petsc_options.empty() && uses_parameter(params, "petsc_options"))
        if (const std::string why = linalg::petsc_options_problem(params.petsc_options); !why.empty())
            usage_error("petsc-options", params.petsc_options, why);
    std::fputs(threads_notes("jamsim replica").c_str(), stderr);
    for (const auto& [kind, text] : advisories(params))
        std::fprintf(stderr, "jamsim replica: warning: %s\n", text.c_str());

    std::optional<System> initial;
    if (!params.initial.empty()) {
        if (const std::string bad = diagnose_initial_source(params.initial); !bad.empty())
            usage_error("initial", params.initial, "a jamsim campaign archive or a LAMMPS data file: " + bad);
        try {
            initial = InitialStates(params.initial).load(params, 0);
        } catch (const InitialStateError& e) {
            usage_error("initial", params.initial, e.reason());  // the option names the value once
        }
    }
    const ReplicaResult result = run_replica(params, {.initial = initial ? &*initial : nullptr});
    write_replica_file(opt.output, params, result);
    const bool by_time = runs_in_time(params);  // the transient is a time (τ) at rate 0
    const double p = mean_after(result.series, &Sample::pressure, params.transient, by_time);
    const double s = mean_after(result.series, &Sample::shear_stress, params.transient, by_time);
    const double steps_per_s =
        static_cast<double>(result.force_evaluations) * static_cast<double>(params.n) / result.wall_seconds;
    char rate[40] = "";  // only for the models that shear at a rate (not QS or the protocols)
    if (uses_parameter(params, "rate")) std::snprintf(rate, sizeof rate, " rate=%.6g", params.rate);
    std::printf("replica %s N=%lld phi=%.6g%s: %zu samples, %.2f s on %d thread%s, %.3g particle-force-"
                "evaluations/s\n",
                params.model.c_str(), static_cast<long long>(params.n), params.phi, rate, result.series.size(),
                result.wall_seconds, kernel_threads(), kernel_threads() == 1 ? "" : "s", steps_per_s);
    std::printf("mean pressure     <p>     = %.10g\n", p);
    std::printf("mean shear stress <sigma> = %.10g\n", s);
    std::printf("(averages over %s >= %g; written to %s)\n", by_time ? "time" : "strain", params.transient,
                opt.output.c_str());
}

}  // namespace

CLI::App* add_replica_command(CLI::App& app) {
    auto opt = std::make_shared<ReplicaOptions>();
    auto* cmd = app.add_subcommand("replica", "Run one sheared replica and write an HDF5 file");
    // One option per row of the parameter table (jamsim/params/parameters.hpp).
    for (const auto& info : parameters()) {
        if (info.flag.empty()) continue;  // derived, or for campaigns only
        std::string help(info.description);
        if (!info.units.empty() && info.units != "1") help += " [" + std::string(info.units) + "]";
        help += "; allowed: " + std::string(info.allowed);
        if (info.key == "model") help += " (" + model_list() + ")";
        const std::string key(info.key);
        // Read as text (for one message naming the option and what is allowed), typed in --help.
        const char* type = !is_numeric(info)                                             ? "TEXT"
                           : std::holds_alternative<double ReplicaParams::*>(info.field) ? "NUMBER"
                                                                                         : "INT";
        cmd->add_option_function<std::string>(
               std::string(info.flag), [opt, key](const std::string& v) { opt->given[key] = v; }, help)
            ->default_str(default_text(info))
            ->type_name(type);
    }
    cmd->add_option("-o,--output", opt->output, "Output HDF5 file")
        ->required()
        ->check(nonempty_path())
        ->type_name("FILE");
    add_threads_option(*cmd);
    cmd->callback([opt] {
        refuse_more_than_one_process("jamsim replica");
        check_threads_environment("jamsim replica", true);
        run(*opt);
    });
    return cmd;
}

}  // namespace jamsim::app
