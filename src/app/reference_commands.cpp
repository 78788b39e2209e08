// Reference output printed from the registries themselves, so that the README's parameter
// table and `--help` cannot drift from the code (a test compares the README with it).
#include "reference_commands.hpp"

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
        const std::string where = info.table.empty() ? std::string("(derived)")
                                                     : "[" + std::string(info.table) + "] " + std::string(info.toml_key);
        const std::string def = default_text(info);
        const std::string used = users_of(info.key);
        if (markdown)
            std::printf("| `%s` | %s | %s | %s | %s | %s | %s | %s |\n", std::string(info.key).c_str(),
                        info.table.empty() ? where.c_str() : ("`" + where + "`").c_str(),
                        info.flag.empty() ? "" : ("`" + std::string(info.flag) + "`").c_str(),
                        info.units.empty() ? "" : std::string(info.units).c_str(),
                        def.empty() ? "\"\"" : def.c_str(), std::string(info.allowed).c_str(),
                        used.c_str(), std::string(info.description).c_str());
        else
            std::printf("%-16s %-24s default %-8s units %-14s used by %s\n    %s; allowed: %s\n",
                        std::string(info.key).c_str(), where.c_str(),
                        def.empty() ? "\"\"" : def.c_str(),
                        info.units.empty() ? "-" : std::string(info.units).c_str(), used.c_str(),
                        std::string(info.description).c_str(), std::string(info.allowed).c_str());
    }
}

void print_models() {
    for (const auto& m : models()) {
        std::string reads;
        for (auto key : m.parameters) reads += (reads.empty() ? "" : ", ") + std::string(key);
        std::printf("%-14s %s: %s\n%14s reads %s (and N, phi, seed, alpha, size_ratio, skin%s)\n",
                    std::string(m.name).c_str(),
                    m.kind == ModelKind::Dynamics ? "dynamics" : "minimisation",
                    std::string(m.summary).c_str(), "", reads.empty() ? "nothing else" : reads.c_str(),
                    m.kind == ModelKind::Dynamics
                        ? "; rate, transient, sample_interval, strain or at rate 0 time"
                        : "");
    }
}

} // namespace

CLI::App* add_parameters_command(CLI::App& app) {
    auto markdown = std::make_shared<bool>(false);
    auto* cmd = app.add_subcommand("parameters", "List every replica parameter (key, campaign "
                                                 "file location, option, units, default, allowed)");
    cmd->add_flag("--markdown", *markdown, "As the README's Markdown table");
    cmd->callback([markdown] { print_parameters(*markdown); });
    return cmd;
}

CLI::App* add_models_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("models", "List the dynamical models and minimisation protocols");
    cmd->callback([] { print_models(); });
    return cmd;
}

} // namespace jamsim::app
