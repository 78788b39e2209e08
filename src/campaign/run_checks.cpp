// The checks `jamsim run` makes on rank 0 before any work (run_checks.hpp).
#include "jamsim/campaign/run_checks.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

/// The archive path the run writes: -o or [campaign] output, through a symlink to the file
/// it names (its lock, checkpoints and growth files are that file's, whichever path a run was
/// given), as MPI-IO is given it.
std::string archive_path(const CampaignSpec& spec, const std::string& override_output) {
    std::string output = override_output.empty() ? spec.output : override_output;
    if (std::error_code ec; std::filesystem::is_symlink(output, ec)) {
        const auto target = std::filesystem::weakly_canonical(output, ec);
        if (!ec) output = target.string();
    }
    return mpi_io_path(spec.path, output);
}

std::string output_named(const CampaignSpec& spec, const std::string& path, bool from_option) {
    return spec.path + (from_option ? ": -o \"" : ": [campaign] output = \"") + path + "\"";
}

/// "" when the run may write `path`; `mode` says how (a new or resumed archive, one extended
/// to longer runs, one grown by more replicas: then `source` maps spec's replicas to the
/// archive's, Archive::check_growth).
std::string check_output(const std::string& path, bool from_option, const CampaignSpec& spec, OutputMode& mode,
                         std::vector<std::int64_t>& source) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (const std::string why = output_path_problem(path); !why.empty())
        return output_named(spec, path, from_option) + " is not allowed: " + why;
    if (fs::exists(path, ec)) {
        if (fs::is_directory(path, ec))
            return output_named(spec, path, from_option) + " is not allowed: a file path, not a directory";
        if (const std::string bad = diagnose_archive_file(path); !bad.empty())
            return spec.path + ": refusing to use the archive: " + bad +
                   " (choose another [campaign] output or -o, or remove the file)";
        const Archive::Fit fit = Archive::check_existing(path, spec);
        if (fit.kind == Archive::Fit::Kind::Same) return "";
        if (fit.kind == Archive::Fit::Kind::Refused)  // another version, unreadable
            return spec.path + ": refusing to use the archive: " + fit.why +
                   " (choose another [campaign] output or -o)";
        const std::string not_longer = Archive::check_extension(path, spec);
        if (not_longer.empty()) {  // the same campaign, run longer
            mode = OutputMode::Extend;
            return "";
        }
        if (not_longer.find("would run shorter") != std::string::npos)  // the one near miss
            return spec.path + ": refusing to use the archive '" + path + "': " + not_longer +
                   " than in it: a campaign can be extended to a larger strain (or time), not "
                   "shortened (choose another [campaign] output or -o)";
        const std::string not_grown = Archive::check_growth(path, spec, source);
        if (not_grown.empty()) {  // the same campaign with more replicas
            mode = OutputMode::Grow;
            return "";
        }
        return spec.path + ": refusing to use the archive: '" + path +
               "' belongs to a different campaign: " + not_grown + " (choose another [campaign] output or -o)";
    }
    // Checkpoints without their archive belong to a run whose archive was removed or moved:
    // a new campaign must not continue from them.
    if (const std::string folder = checkpoint_folder(path); fs::is_directory(folder, ec) && !fs::is_empty(folder, ec))
        return spec.path + ": refusing to start '" + path + "': the checkpoint folder '" + folder +
               "' of an earlier run is there without its archive (restore the archive to "
               "continue that run, or remove the folder to start afresh)";
    return check_output_folder(path, from_option, spec, true);
}

std::string check_output_folder(const std::string& path, bool from_option, const CampaignSpec& spec, bool create) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (const std::string why = output_path_problem(path); !why.empty())
        return output_named(spec, path, from_option) + " is not allowed: " + why;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    const auto quoted = [](const fs::path& f) {  // appended, not '+': GCC 12's -Wrestrict misfires on that here
        std::string out(1, '\'');
        out.append(f.string()).push_back('\'');
        return out;
    };
    const auto refuse = [&](const std::string& why) {
        std::string out = output_named(spec, path, from_option);
        out.append(" is not allowed: a file in a writable directory, or one that can be made (").append(why);
        return out.append(")");
    };
    if (fs::is_directory(dir, ec))
        return ::access(dir.c_str(), W_OK) == 0 ? "" : refuse(quoted(dir) + " is not writable");
    fs::path existing = dir;  // the nearest folder above that exists: the new ones go there
    while (existing.has_parent_path() && existing != existing.parent_path() && !fs::exists(existing, ec))
        existing = existing.parent_path();
    if (!fs::exists(existing, ec)) existing = ".";
    if (!fs::is_directory(existing, ec)) return refuse(quoted(existing) + " is not a directory");
    if (::access(existing.c_str(), W_OK) != 0)
        return refuse(quoted(dir) + " does not exist and " + quoted(existing) + " is not writable");
    if (create && !fs::create_directories(dir, ec) && ec)
        return refuse("making " + quoted(dir) + " failed: " + ec.message());
    return "";
}

/// Every checkpoint beside the archive must belong to one of this campaign's replicas, so a
/// stale or foreign one stops the run before any work (it is left as it is). A damaged one
/// (unreadable) is left to its replica, which warns, removes it and starts again.
std::string check_checkpoints(const std::string& output, const CampaignSpec& spec) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path folder = checkpoint_folder(output);
    // Something else under the folder's name would stop the run at its first checkpoint.
    // (Appended, not '+': GCC 12's -Wrestrict misfires on that here.)
    if (fs::symlink_status(folder, ec).type() != fs::file_type::not_found && !fs::is_directory(folder, ec)) {
        std::string why(1, '\'');
        why.append(folder.string()).append("' is not allowed: the name of the folder of ").append(output);
        return why.append("'s checkpoints, and it is not a folder (rename or remove it)");
    }
    if (!fs::is_directory(folder, ec)) return "";
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        // A folder, FIFO or device under the name of a replica's file: reading it blocked for
        // good (a FIFO) or stopped the run with the C++ library's words, naming nothing.
        std::error_code type_error;
        const fs::file_type type = entry.status(type_error).type();
        if ((name.starts_with("replica_") || name.starts_with("end_") || name.starts_with("rebuild_")) &&
            type != fs::file_type::regular && type != fs::file_type::not_found && !type_error) {
            std::string why = spec.path + ": '";
            why.append(entry.path().string()).append("' is not a regular file (a folder, a FIFO, a device), which is ");
            return why.append("not allowed: jamsim keeps a replica's checkpoint, end state or progress note under that "
                              "name; remove it and run the same command again");
        }
        long long id = -1;
        char tail[8] = {};
        if (std::sscanf(name.c_str(), "replica_%lld.h%7s", &id, tail) != 2 || std::string(tail) != "5")
            continue;  // not a checkpoint (e.g. a .tmp left by a kill)
        if (id < 0 || id >= static_cast<long long>(spec.replicas.size()))
            return spec.path + ": checkpoint '" + entry.path().string() + "' names replica " + std::to_string(id) +
                   ", this campaign has " + std::to_string(spec.replicas.size()) +
                   ": remove it or choose another output";
        try {
            check_checkpoint_header(entry.path().string(), spec.replicas[static_cast<std::size_t>(id)]);
        } catch (const CheckpointUnreadable&) {
            continue;  // damaged: its replica removes it with a warning and starts again
        } catch (const CheckpointError& e) { return spec.path + ": " + e.what(); }
    }
    return "";
}

/// "" when every replica of the archive at `output` that started from [run] initial would
/// start from the same state today (grow_source: the archive's id of each replica of a grown
/// campaign, empty otherwise); else which would not, and what to do.
std::string initial_source_changed(const InitialStates& source, const CampaignSpec& spec, const std::string& output,
                                   const std::vector<std::int64_t>& grow_source) {
    InitialRecords recorded = read_initial_records(output);
    if (!grow_source.empty()) {  // to this campaign's ids
        InitialRecords mapped;
        for (const std::int64_t from : grow_source) {
            const bool kept = from >= 0 && static_cast<std::size_t>(from) < recorded.source.size();
            mapped.source.push_back(kept ? recorded.source[static_cast<std::size_t>(from)] : 0);
            mapped.state.push_back(kept ? recorded.state[static_cast<std::size_t>(from)] : 0);
        }
        recorded = std::move(mapped);
    }
    const std::string why = source.changed_since(spec.replicas, recorded.source, recorded.state);
    return why.empty() ? "" : spec.path + ": " + why;
}

/// `path` as MPI-IO is given it: Open MPI's MPI-IO overflows a buffer (and aborts the job)
/// on names of more than 244 characters (measured with Open MPI 4.1: 244 opens, 245 aborts),
/// and an extension or a growth opens PATH.extending or PATH.growing through it too, so a
/// path of more than 234 is given relative to the working directory, and one that is long
/// even so is refused with jamsim's words.
std::string mpi_io_path(const std::string& spec_path, const std::string& path) {
    constexpr std::size_t kLongest = 244 - std::char_traits<char>::length(".extending");
    if (path.size() <= kLongest) return path;
    std::error_code ec;
    const std::string relative = std::filesystem::proximate(path, ec).string();
    if (!ec && relative.size() <= kLongest) return relative;
    throw SpecError(spec_path + ": output = \"" + path.substr(0, 60) + "...\" (" + std::to_string(path.size()) +
                    " characters) is not allowed: an archive path of at most " + std::to_string(kLongest) +
                    " characters (Open MPI's MPI-IO takes no longer names), also relative to the working directory; "
                    "run from a folder nearer the archive, or choose a shorter path");
}

/// PETSc options (campaign-wide, [model] petsc_options) that PETSc does not recognise or the
/// CD0 solver does not use: refused before any work, by PETSc itself (the table's check has
/// refused those no PETSc solver would see).
std::string check_petsc_options(const CampaignSpec& spec) {
    for (const ReplicaParams& p : spec.replicas) {
        if (!uses_parameter(p, "petsc_options")) continue;
        try {
            if (const std::string why = linalg::petsc_environment_problem(); !why.empty())
                return spec.path + ": " + why;
        } catch (const std::exception& e) { return spec.path + ": PETSc's options could not be checked: " + e.what(); }
        if (p.petsc_options.empty()) return "";
        try {
            if (const std::string why = linalg::petsc_options_problem(p.petsc_options); !why.empty())
                return spec.path + ": [model] petsc_options = \"" + p.petsc_options + "\" is not allowed: " + why;
        } catch (const std::exception& e) {
            return spec.path + ": [model] petsc_options = \"" + p.petsc_options +
                   "\" could not be checked: " + e.what();
        }
        return "";  // the same options for every replica: one check
    }
    return "";
}

/// Advisory warnings (limits not refused), each kind once; the archive keeps them too (its
/// root attribute `warnings`).
std::vector<std::string> advisories(const CampaignSpec& spec) {
    std::vector<std::string> lines;
    for (const std::string& line : campaign_warnings(spec)) lines.push_back(spec.path + ": " + line);
    // A file without [run] is allowed, but the length and sampling of a dynamics run are
    // then the defaults: say which, so that an omission is not mistaken for a choice.
    if (spec.run_table || spec.replicas.empty()) return lines;
    std::string defaults;
    for (const auto& info : parameters()) {
        if (info.table != "run" ||
            (info.key != "strain" && info.key != "time" && info.key != "transient" && info.key != "sample_interval"))
            continue;
        const auto used = std::find_if(spec.replicas.begin(), spec.replicas.end(),
                                       [&](const ReplicaParams& p) { return uses_parameter(p, info.key); });
        if (used == spec.replicas.end()) continue;
        defaults.append(defaults.empty() ? "" : ", ")
            .append(info.key)
            .append(" = ")
            .append(show_value(get_value(*used, info)));
    }
    if (!defaults.empty())
        lines.push_back(spec.path + ": no [run] table: the run takes the defaults " + defaults +
                        " (campaigns/TEMPLATE.toml lists every key)");
    return lines;
}

}  // namespace jamsim
