// Reference output printed from the registries themselves, so that the parameter table of
// campaigns/README.md and `--help` cannot drift from the code (a test compares the two).
#include "reference_commands.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim::app {

namespace {

/// Models whose replicas read `key` (at a rate > 0 and at rate 0).
std::string users_of(std::string_view key) {
    std::string out;
    std::size_t count = 0;
    for (const auto& m : models()) {
        ReplicaParams p;
        p.model = std::string(m.name);
        p.initial = "other.h5";  // the parameters recorded only when these are set
        p.rate_ladder = "down";
        p.frame_interval = 1.0;
        bool used = false;
        for (double rate : {1.0, 0.0}) {
            p.rate = rate;
            used = used || uses_parameter(p, key);
        }
        if (!used) continue;
        out += (out.empty() ? "" : ", ") + p.model;
        ++count;
    }
    return count == models().size() ? "all" : out;
}

void print_parameters(bool markdown) {
    if (markdown) {
        std::printf("| key | campaign file | option | units | default | allowed | used by | meaning |\n");
        std::printf("|---|---|---|---|---|---|---|---|\n");
    }
    for (const auto& info : parameters()) {
        const std::string where = info.table.empty()
                                      ? std::string("(derived)")
                                      : "[" + std::string(info.table) + "] " + std::string(info.toml_key);
        const std::string def = default_text(info);
        const std::string used = users_of(info.key);
        if (markdown)
            std::printf("| `%s` | %s | %s | %s | %s | %s | %s | %s |\n", std::string(info.key).c_str(),
                        info.table.empty() ? where.c_str() : ("`" + where + "`").c_str(),
                        info.flag.empty() ? "" : ("`" + std::string(info.flag) + "`").c_str(),
                        info.units.empty() ? "" : std::string(info.units).c_str(), def.empty() ? "\"\"" : def.c_str(),
                        std::string(info.allowed).c_str(), used.c_str(), std::string(info.description).c_str());
        else
            std::printf("%-16s %-24s default %-8s units %-14s used by %s\n    %s; allowed: %s\n",
                        std::string(info.key).c_str(), where.c_str(), def.empty() ? "\"\"" : def.c_str(),
                        info.units.empty() ? "-" : std::string(info.units).c_str(), used.c_str(),
                        std::string(info.description).c_str(), std::string(info.allowed).c_str());
    }
}

/// A campaign file listing every key with its default, units, allowed values and readers:
/// the required keys set, every other one commented out at its default.
void print_template() {
    std::printf("# jamsim campaign template: every key with its default, units, allowed values and the\n"
                "# models that read it. Printed by `jamsim parameters --template` from the parameter\n"
                "# table; copy it, set what you need, delete the rest. A key the model does not read is\n"
                "# refused. Paths (output, initial) are relative to the working directory of jamsim run,\n"
                "# not to this file (`jamsim run FILE -o PATH` replaces output). A table or key left out\n"
                "# takes its defaults; without [run] a dynamics replica runs to strain 2 with transient 0\n"
                "# (jamsim run warns).\n"
                "# Run: mpirun -n 4 jamsim run FILE.toml   (check first: jamsim run --dry-run FILE.toml)\n\n"
                "[campaign]\nname = \"my-campaign\"           # required\n"
                "output = \"out/my-campaign.h5\"  # required: the archive\n");
    const auto value = [](const ParamInfo& info) {
        const std::string v = default_text(info);
        return is_numeric(info) ? v : "\"" + v + "\"";
    };
    for (const char* table : {"model", "potential", "system", "run", "sweep"}) {
        std::printf("\n[%s]\n", table);
        if (std::string(table) == "potential")
            std::printf("# name = \"harmonic\"  # or \"hertzian\": presets of alpha (give name or alpha)\n");
        for (const auto& info : parameters()) {
            if (info.table != table) continue;
            const std::string key(info.toml_key);
            const std::string units =
                info.units.empty() || info.units == "1" ? "" : " [" + std::string(info.units) + "]";
            const std::string comment = std::string(info.description) + units +
                                        "; allowed: " + std::string(info.allowed) + "; read by: " + users_of(info.key);
            if (info.key == "model") {
                std::printf("name = \"RD0\"  # %s (jamsim models lists them)\n", comment.c_str());
            } else if (info.key == "N" || info.key == "phi" || info.key == "rate") {
                std::printf("%s = [%s]  # %s; a list, expanded as a grid with the others\n", key.c_str(),
                            value(info).c_str(), comment.c_str());
            } else if (info.key == "seed") {
                std::printf("seeds = 1  # a count (seeds 1..n) or a list [3, 7]; %s\n", comment.c_str());
            } else {
                std::printf("# %s = %s  # %s\n", key.c_str(), value(info).c_str(), comment.c_str());
            }
        }
    }
    std::printf("# points = [{N = 4096, phi = 0.843, rate = 1e-5}]  # extra non-grid points, each with every seed (or "
                "its own: seeds = [4, 9])\n");
}

/// The keys a model reads besides its own list (ModelInfo::parameters), from uses_parameter
/// over the settings that switch keys on (rate > 0 or 0, a rate ladder, frames, stored
/// initial states), in the parameter table's order; a key read at one kind of rate only says
/// which ("strain (at rate > 0), time (at rate 0)").
std::string keys_read_besides_own(const ModelInfo& m) {
    ReplicaParams sheared, at_rest;
    sheared.model = at_rest.model = std::string(m.name);
    sheared.rate = 1e-4;
    at_rest.rate = 0.0;
    for (ReplicaParams* q : {&sheared, &at_rest}) {
        q->initial = "initial.h5";
        q->frame_interval = 1.0;
        q->rate_ladder = "down";
    }
    std::string out;
    for (const auto& info : parameters()) {
        if (info.key == "model" || std::find(m.parameters.begin(), m.parameters.end(), info.key) != m.parameters.end())
            continue;
        const bool when_sheared = uses_parameter(sheared, info.key), at_rate_0 = uses_parameter(at_rest, info.key);
        if (!when_sheared && !at_rate_0) continue;
        out += (out.empty() ? "" : ", ") + std::string(info.key);
        if (when_sheared != at_rate_0) out += when_sheared ? " (at rate > 0)" : " (at rate 0)";
    }
    return out;
}

void print_models() {
    for (const auto& m : models()) {
        std::string reads;
        for (auto key : m.parameters) reads += (reads.empty() ? "" : ", ") + std::string(key);
        std::printf("%-14s %s: %s\n%14s reads %s (and %s)\n", std::string(m.name).c_str(),
                    m.kind == ModelKind::Dynamics ? "dynamics" : "minimisation", std::string(m.summary).c_str(), "",
                    reads.empty() ? "nothing else" : reads.c_str(), keys_read_besides_own(m).c_str());
    }
}

}  // namespace

CLI::App* add_parameters_command(CLI::App& app) {
    auto markdown = std::make_shared<bool>(false);
    auto campaign_template = std::make_shared<bool>(false);
    auto* cmd = app.add_subcommand("parameters", "List every replica parameter (key, campaign "
                                                 "file location, option, units, default, allowed)");
    cmd->add_flag("--markdown", *markdown, "As the Markdown table of campaigns/README.md");
    cmd->add_flag("--template", *campaign_template, "As a commented campaign file (campaigns/TEMPLATE.toml)");
    cmd->callback([markdown, campaign_template] {
        if (*markdown && *campaign_template)  // one of them would be silently dropped
            throw CLI::ValidationError("jamsim parameters: --markdown is not allowed with --template: one form at a "
                                       "time (the table of campaigns/README.md, or a campaign file)");
        if (*campaign_template)
            print_template();
        else
            print_parameters(*markdown);
    });
    return cmd;
}

CLI::App* add_models_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("models", "List the dynamical models and minimisation protocols");
    cmd->callback([] { print_models(); });
    return cmd;
}

}  // namespace jamsim::app
