#pragma once
// The checks `jamsim run` makes on rank 0 before any work: the output archive, the
// checkpoints beside it, the [run] initial source, PETSc options, advisories.
#include <cstdint>
#include <string>
#include <vector>

#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/io/initial_states.hpp"

namespace jamsim {

/// What a run does with an existing archive of its campaign.
enum class OutputMode : int { Fresh = 0, Extend = 1, Grow = 2 };

/// The archive path the run writes: `override_output` (-o) or [campaign] output, through a
/// symlink to the file it names (its lock, checkpoints and growth files are that file's,
/// whichever path a run was given), as MPI-IO is given it (mpi_io_path).
std::string archive_path(const CampaignSpec& spec, const std::string& override_output);
/// `FILE: [campaign] output = "PATH"` or, for an output given as -o (`from_option`),
/// `FILE: -o "PATH"`: how a refusal of the output names it (it used to blame the campaign
/// file for a bad -o).
std::string output_named(const CampaignSpec& spec, const std::string& path, bool from_option);

/// "" when the run may write `path`; `mode` says how (a new or resumed archive, one extended
/// to longer runs, one grown by more replicas: then `source` maps spec's replicas to the
/// archive's, Archive::check_growth). `from_option`: -o gave `path` (output_named).
std::string check_output(const std::string& path, bool from_option, const CampaignSpec& spec, OutputMode& mode,
                         std::vector<std::int64_t>& source);
/// "" when the folder of `path` exists and is writable, or can be made below the nearest
/// folder that exists (then, with `create`, it is made, as `mkdir -p` would: the campaigns
/// shipped write to out/...); else why not, the same words in the dry run and the run.
std::string check_output_folder(const std::string& path, bool from_option, const CampaignSpec& spec, bool create);
/// Every checkpoint beside the archive must belong to one of this campaign's replicas ("" or
/// why not); a damaged (unreadable) one is left to its replica.
std::string check_checkpoints(const std::string& output, const CampaignSpec& spec);
/// "" when every replica of the archive at `output` that started from [run] initial would
/// start from the same state today; else which would not, and what to do.
std::string initial_source_changed(const InitialStates& source, const CampaignSpec& spec, const std::string& output,
                                   const std::vector<std::int64_t>& grow_source);
/// `path` as MPI-IO is given it (relative when too long); throws SpecError when too long even so.
std::string mpi_io_path(const std::string& spec_path, const std::string& path);
/// PETSc options PETSc does not recognise or the CD0 solver does not use ("" when none).
std::string check_petsc_options(const CampaignSpec& spec);
/// Advisory warnings ("FILE: what"), each kind once: limits that are not refused, and the
/// defaults a file without [run] takes.
std::vector<std::string> advisories(const CampaignSpec& spec);

}  // namespace jamsim
