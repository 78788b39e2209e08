// Rank 0's checks before a run (lifecycle.hpp, check_run): every refusal of `jamsim run`
// that does not need the other ranks.
#include <filesystem>
#include <unordered_map>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/archive_lock.hpp"
#include "jamsim/campaign/lifecycle.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

namespace {

/// A growth that a kill interrupted is completed (after its rename) or undone (before it),
/// unless another live run holds the archive (refused later for that reason).
void finish_interrupted_growth(const CampaignSpec& spec, RunDecision& d) {
    try {
        ArchiveLock::check_free(d.output);
        if (const std::string done = Archive::finish_growth(d.output); !done.empty()) d.notes.push_back(done);
    } catch (const ArchiveBusy&) {
    } catch (const h5::Error& e) { throw SpecError(spec.path + ": " + e.what()); }
}

/// An archive whose creation a kill interrupted (its marker beside it) is removed, to be
/// created anew, and what an interrupted extension left beside it, unless another live run
/// holds it (refused later for that reason).
void undo_interrupted_creation(const CampaignSpec& spec, RunDecision& d) {
    try {
        ArchiveLock::check_free(d.output);
        if (const std::string done = Archive::undo_interrupted_creation(d.output); !done.empty())
            d.notes.push_back(done);
        if (const std::string done = Archive::remove_interrupted_extension(d.output); !done.empty())
            d.notes.push_back(done);
        for (const std::string& left : remove_stale_mpi_locks(d.output))
            d.notes.push_back("removed '" + left + "', an MPI lock file left by a run that was killed or aborted");
    } catch (const ArchiveBusy&) {
    } catch (const h5::Error& e) { throw SpecError(spec.path + ": " + e.what()); }
}

/// "" unless two replicas that differ only in their seed would start from one LAMMPS data
/// file's state: the seed draws the random start and the thermal models' noise alone, so
/// without a temperature they would be the same bits (false seeds, false error bars).
std::string seeds_without_effect(const CampaignSpec& spec) {
    const ReplicaParams& first = spec.replicas.front();
    if (first.initial_match == "id")
        return "[run] initial_match = \"id\" is not allowed with [run] initial = \"" + first.initial +
               "\": a LAMMPS data file holds one state, which starts every replica (initial_match picks a "
               "replica of a source archive); leave initial_match out";
    std::unordered_map<std::string, std::size_t> seen;  // the replica's parameters but its seed
    for (std::size_t id = 0; id < spec.replicas.size(); ++id) {
        ReplicaParams p = spec.replicas[id];
        if (uses_parameter(p, "temperature")) continue;
        const std::uint64_t seed = p.seed;
        p.seed = 0;
        const auto [it, fresh] = seen.emplace(describe(p), id);
        if (fresh) continue;
        return "[sweep] seeds: replicas " + std::to_string(it->second) + " and " + std::to_string(id) + " (seed " +
               std::to_string(spec.replicas[it->second].seed) + " and " + std::to_string(seed) +
               ") are not allowed with [run] initial = \"" + first.initial +
               "\": a LAMMPS data file starts every replica from its one state, and " + p.model +
               " draws no random numbers, so they would be the same bits; use one seed (seeds = 1), or an "
               "archive of states of several seeds as initial";
    }
    return "";
}

/// Every replica must find its starting state ([run] initial) before any work, and the
/// replicas already in the archive must start from the same states as when they ran.
std::string check_initial_states(const CampaignSpec& spec, const RunDecision& d) {
    if (spec.replicas.front().initial.empty()) return "";
    const std::string& path = spec.replicas.front().initial;
    if (const std::string bad = diagnose_initial_source(path); !bad.empty())
        return spec.path + ": [run] initial = \"" + path +
               "\" is not allowed: a jamsim campaign archive or a LAMMPS data file (" + bad + ")";
    try {
        const InitialStates source(spec.replicas.front().initial);
        for (std::size_t id = 0; id < spec.replicas.size(); ++id)
            source.match(spec.replicas[id], static_cast<std::int64_t>(id));
        if (source.is_data_file())
            if (const std::string why = seeds_without_effect(spec); !why.empty()) return spec.path + ": " + why;
        if (std::filesystem::exists(d.output)) return initial_source_changed(source, spec, d.output, d.grow_source);
    } catch (const InitialStateError& e) { return spec.path + ": " + e.what(); }
    return "";
}

/// The checks on a read campaign, in order; the first refusal is `d.error`.
void check_campaign(const RunRequest& request, const CampaignSpec& spec, RunDecision& d) {
    d.spec_text = spec.text;
    d.output = archive_path(spec, request.output);
    d.output_given = !request.output.empty();
    // Before anything opens it: a FIFO blocked the first open() for good, deaf to SIGTERM.
    if (std::error_code ec; !std::filesystem::is_directory(d.output, ec))  // the folder checks say that
        if (const std::string odd = not_a_regular_file(d.output); !odd.empty())
            throw SpecError(output_named(spec, d.output, d.output_given) + " is not allowed: a regular file: " + odd);
    // What a kill or a failed write left beside the archive goes first: its bytes are free
    // for the size check (a failed extension's PATH.extending used to take them, and the
    // rerun was refused for want of the space it held).
    if (!request.dry_run) {
        undo_interrupted_creation(spec, d);
        finish_interrupted_growth(spec, d);
    }
    // Size and memory before anything is created.
    d.capacity = estimate_capacity(spec, d.output, request.ranks, request.node_ranks);
    d.sized = true;
    if (std::string too_large = check_capacity(d.capacity, request.limits, spec, d.output); !too_large.empty()) {
        if (!request.dry_run) throw SpecError(too_large);
        d.dry_run_refusal = std::move(too_large);
    }
    // A dry run writes nothing, but an existing archive it names must fit the campaign (one
    // whose creation was interrupted is made anew).
    std::error_code ec;
    const bool half_made = std::filesystem::exists(Archive::creation_marker(d.output), ec);
    if (!request.dry_run || (std::filesystem::exists(d.output) && !half_made))
        d.error = check_output(d.output, d.output_given, spec, d.mode, d.grow_source);
    else
        d.error = check_output_folder(d.output, d.output_given, spec, false);  // what the run would refuse
    for (const std::int64_t from : d.grow_source) d.grow_kept += from >= 0;
    if (d.error.empty() && d.dry_run_refusal.empty() && (d.mode == OutputMode::Extend || d.mode == OutputMode::Grow)) {
        d.capacity.beside_old = true;  // checked again: the new archive is written whole first
        if (std::string too_large = check_capacity(d.capacity, request.limits, spec, d.output); !too_large.empty()) {
            if (!request.dry_run) throw SpecError(too_large);
            d.dry_run_refusal = std::move(too_large);
        }
    }
    // The checkpoints beside the archive are keyed by its replica ids (before a growth, those
    // of the archive's campaign).
    if (d.error.empty())
        d.error = check_checkpoints(d.output, d.mode == OutputMode::Grow ? read_stored_campaign(d.output).spec : spec);
    if (d.error.empty()) d.error = check_petsc_options(spec);
    if (d.error.empty()) d.warnings = advisories(spec);
    if (d.error.empty()) d.error = check_initial_states(spec, d);
}

}  // namespace

RunDecision check_run(const RunRequest& request) {
    RunDecision d;
    try {
        check_campaign(request, load_campaign(request.spec_path, request.max_replicas, request.node_ranks), d);
    } catch (const SpecError& e) {
        d.error = e.what();
    } catch (const std::exception& e) {  // any other failure (an unreadable file): said in words
        d.error = request.spec_path + ": " + e.what();
    }
    // An archive that another live run writes is refused for that reason, whatever it looks
    // like now (it may be half created): the holder's name says what to do.
    if (!request.dry_run && !d.output.empty()) try {
            ArchiveLock::check_free(d.output);
        } catch (const ArchiveBusy& e) { d.error = e.what(); }
    return d;
}

}  // namespace jamsim
