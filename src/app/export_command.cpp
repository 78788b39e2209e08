// `jamsim export`: final configurations of finished replicas of a campaign archive as LAMMPS
// data files (atom_style sphere, the sheared cell as a tilted box) or H5MD files. Everything
// is checked before anything is written; each file is written under a temporary name and
// renamed, and a failure removes what this call wrote.
#include "export_command.hpp"
#include "option_checks.hpp"
#include "exit_status.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "jamsim/core/parse_number.hpp"
#include "jamsim/core/version.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/io/h5md.hpp"
#include "jamsim/io/lammps_data.hpp"
#include "jamsim/io/stored_replicas.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/io/temporary_file.hpp"

namespace jamsim::app {

namespace {

struct ExportOptions {
    std::string archive;
    std::vector<std::string> replicas;
    std::string output;
    std::string format;
};

/// Refused input: one message on stderr, exit status 2, nothing written.
struct Refused {
    std::string message;
};

[[noreturn]] void refuse(const std::string& message) { throw Refused{message}; }

bool parse_id(std::string_view s, std::int64_t& out) { return parse_whole_text(s, out) && out >= 0; }

/// "3", "0,2,5", "4-7", "done" (every finished replica), possibly repeated.
std::vector<std::int64_t> selected_ids(const ExportOptions& opt, const StoredReplicas& stored) {
    std::set<std::int64_t> ids;
    const std::int64_t r = stored.size();
    const std::string range = r > 0 ? "0 to " + std::to_string(r - 1) : "none";
    for (const std::string& list : opt.replicas) {
        std::size_t start = 0;
        while (start <= list.size()) {
            const std::size_t comma = std::min(list.find(',', start), list.size());
            const std::string item = list.substr(start, comma - start);
            start = comma + 1;
            if (item == "done") {
                for (std::int64_t k = 0; k < r; ++k)
                    if (stored.status(k) == 2) ids.insert(k);
                continue;
            }
            std::int64_t lo = 0, hi = 0;
            const auto dash = item.find('-');
            const bool ok = dash == std::string::npos
                                ? parse_id(item, lo) && (hi = lo, true)
                                : parse_id(std::string_view(item).substr(0, dash), lo) &&
                                      parse_id(std::string_view(item).substr(dash + 1), hi) && lo <= hi;
            if (!ok)
                refuse("--replica = '" + list +
                       "' is not allowed: replica ids (3), lists (0,2,5), ranges (4-7) "
                       "or done (every finished replica)");
            if (hi >= r) refuse("--replica = " + item + " is not allowed: '" + opt.archive + "' has replicas " + range);
            for (std::int64_t k = lo; k <= hi; ++k) ids.insert(k);
        }
    }
    if (ids.empty())
        refuse("'" + opt.archive + "' has no finished replica to export (jamsim status " + opt.archive + ")");
    for (std::int64_t k : ids)
        if (stored.status(k) != 2)
            refuse("replica " + std::to_string(k) + " of '" + opt.archive + "' is " + status_word(stored.status(k)) +
                   ": only a done replica has a final configuration (jamsim status " + opt.archive + ")");
    return {ids.begin(), ids.end()};
}

std::string output_for(const std::string& pattern, std::int64_t id) {
    std::string out = pattern;
    for (std::size_t at; (at = out.find("{id}")) != std::string::npos;) out.replace(at, 4, std::to_string(id));
    return out;
}

std::string format_of(const ExportOptions& opt) {
    if (!opt.format.empty()) {
        if (opt.format != "lammps" && opt.format != "h5md")
            refuse("--format = " + opt.format + " is not allowed: lammps or h5md");
        return opt.format;
    }
    const std::string ext = std::filesystem::path(opt.output).extension().string();
    return ext == ".h5md" || ext == ".h5" ? "h5md" : "lammps";
}

void check_output(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (const std::string why = odd_file_name(path); !why.empty()) refuse("-o = '" + path + "' is not allowed: " + why);
    if (!fs::is_directory(dir, ec))
        refuse("-o = '" + path + "' is not allowed: a file in an existing directory ('" + dir.string() +
               "' does not exist)");
    if (::access(dir.c_str(), W_OK) != 0)
        refuse("-o = '" + path + "' is not allowed: a file in a writable directory ('" + dir.string() +
               "' is not writable)");
    if (const std::string why = name_fits_folder(p); !why.empty()) refuse("-o = '" + path + "' is not allowed: " + why);
    if (fs::exists(fs::symlink_status(p, ec)))
        refuse("-o = '" + path +
               "' is not allowed: it exists (jamsim export does not overwrite; remove it or "
               "choose another name)");
}

std::string describe(const StoredReplica& r) {
    std::string out = r.model + ", N = " + show_value(r.n) + ", phi = " + show_value(r.phi);
    if (!std::isnan(r.rate)) out += ", rate = " + show_value(r.rate);
    return out + ", seed = " + show_value(r.seed);
}

std::string lammps_title(const StoredReplica& r, const std::string& archive, const std::string& campaign) {
    char obs[256];
    std::snprintf(obs, sizeof obs, "final row: E/N = %.17g, p = %.17g, sigma = %.17g", r.energy_per_particle,
                  r.pressure, r.shear_stress);
    return "LAMMPS data file: jamsim " + std::string(kVersion) + " export of replica " + std::to_string(r.id) +
           " of '" + archive + "' (campaign " + campaign + ", " + describe(r) +
           "); atom_style sphere, type 1 d = 1, type 2 d = size_ratio; Lees-Edwards strain gamma = xy/L = " +
           show_value(r.final.box_strain) + "; " + obs;
}

int run_export(const ExportOptions& opt) {
    if (const std::string bad = diagnose_archive_file(opt.archive); !bad.empty()) refuse(bad);
    const StoredReplicas stored(opt.archive);
    const std::vector<std::int64_t> ids = selected_ids(opt, stored);
    const std::string format = format_of(opt);
    if (ids.size() > 1 && opt.output.find("{id}") == std::string::npos)
        refuse("-o = '" + opt.output + "' is not allowed for " + std::to_string(ids.size()) +
               " replicas: a name with {id}, replaced by each replica's id (replica_{id}." +
               (format == "h5md" ? "h5md" : "data") + ")");
    std::vector<std::string> outputs;
    for (std::int64_t id : ids) {
        outputs.push_back(output_for(opt.output, id));
        check_output(outputs.back());
    }
    // Read every replica before writing anything: a replica that cannot be read writes nothing.
    std::vector<StoredReplica> replicas;
    for (std::int64_t id : ids) {
        replicas.push_back(stored.read(id));
        if (const std::string why = damaged_final(replicas.back().final); !why.empty())
            refuse("replica " + std::to_string(id) + " of '" + opt.archive + "' cannot be exported: its final state " +
                   why + "; jamsim writes no such state (a hand-edited or damaged archive?)");
    }

    std::vector<std::string> written;
    try {
        for (std::size_t i = 0; i < replicas.size(); ++i) {
            const std::string tmp = make_temporary_beside(outputs[i]);
            try {
                if (format == "h5md")
                    write_h5md(tmp, replicas[i], opt.archive, stored.campaign());
                else
                    write_lammps_data(tmp, replicas[i].final,
                                      lammps_title(replicas[i], opt.archive, stored.campaign()));
                std::filesystem::rename(tmp, outputs[i]);
            } catch (...) {
                std::error_code ignored;
                std::filesystem::remove(tmp, ignored);
                throw;
            }
            written.push_back(outputs[i]);
        }
    } catch (...) {
        for (const std::string& path : written) {
            std::error_code ignored;
            std::filesystem::remove(path, ignored);
        }
        throw;
    }
    for (std::size_t i = 0; i < replicas.size(); ++i)
        std::printf("replica %lld (%s, strain gamma = %s): %s (%s)\n", static_cast<long long>(replicas[i].id),
                    describe(replicas[i]).c_str(), show_value(replicas[i].final.box_strain).c_str(), outputs[i].c_str(),
                    format == "h5md" ? "H5MD" : "LAMMPS data, atom_style sphere");
    return 0;
}

}  // namespace

CLI::App* add_export_command(CLI::App& app) {
    auto opt = std::make_shared<ExportOptions>();
    auto* cmd =
        app.add_subcommand("export", "Write finished replicas' final configurations as LAMMPS data or H5MD files");
    cmd->add_option("archive", opt->archive, "Campaign archive (HDF5)")->required()->type_name("FILE");
    cmd->add_option("-r,--replica", opt->replicas,
                    "Replica ids: 3, 0,2,5, 4-7 or done (every finished replica); repeatable")
        ->required()
        ->type_name("IDS");
    cmd->add_option("-o,--output", opt->output,
                    "Output file; {id} is replaced by the replica id (required for several replicas)")
        ->required()
        ->check(nonempty_path())
        ->type_name("FILE");
    cmd->add_option("--format", opt->format,
                    "lammps (data file, atom_style sphere) or h5md; default from the name: .h5md or .h5 -> h5md, "
                    "else lammps")
        ->type_name("FORMAT");
    cmd->callback([opt] {
        refuse_more_than_one_process("jamsim export");
        int rc = 1;
        try {
            rc = run_export(*opt);
        } catch (const Refused& r) {
            std::fprintf(stderr, "jamsim export: %s\n", r.message.c_str());
            rc = kExitRefused;
        } catch (const std::exception& e) { std::fprintf(stderr, "jamsim export: %s (nothing written)\n", e.what()); }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
