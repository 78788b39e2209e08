#pragma once
// A replica's checkpoint on disk: one serial HDF5 file per running replica, beside the
// campaign archive (ARCHIVE.checkpoints/replica_<id>.h5), written by the replica's rank as
// PATH.tmp, fsynced and renamed over the previous one, so a kill at any moment leaves either
// the old or the new checkpoint whole. Removed when the replica finishes.
#include <optional>
#include <stdexcept>
#include <string>

#include "jamsim/run/replica.hpp"

namespace jamsim {

/// A checkpoint that cannot be used (another replica, campaign or jamsim version, or a
/// damaged file); the message names the file and why.
struct CheckpointError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A checkpoint file that HDF5 cannot read at all (truncated, zeroed): damaged, not foreign.
struct CheckpointUnreadable : CheckpointError {
    using CheckpointError::CheckpointError;
};

/// Folder of an archive's checkpoints, and the file of replica `id`.
std::string checkpoint_folder(const std::string& archive_path);
std::string checkpoint_path(const std::string& archive_path, std::int64_t id);

/// The cheap part of read_checkpoint's checks (format and replica, from two attributes), for
/// scanning many checkpoints before a run; throws CheckpointError (CheckpointUnreadable for a
/// file HDF5 cannot open or read).
void check_checkpoint_header(const std::string& path, const ReplicaParams& p);

/// How far a running replica has got, between its checkpoints: a one-line text file beside
/// its checkpoint (ARCHIVE.checkpoints/replica_<id>.progress: "FRACTION UNIX_SECONDS"),
/// replaced by a rename every few seconds (jamsim status reads it; the farm removes it when
/// the replica finishes, and an interrupted replica's note says where it stopped).
std::string progress_note_path(const std::string& archive_path, std::int64_t id);
/// Writes the note (a failure to write is ignored: the note only informs).
void write_progress_note(const std::string& path, double fraction);
/// The note's fraction of the replica's steps and its age in seconds; nullopt when there is
/// none or it does not parse.
struct ProgressNote {
    double fraction = 0, age_seconds = 0;
};
std::optional<ProgressNote> read_progress_note(const std::string& path);

/// The end state of a replica of a rate ladder, which its successor starts from.
std::string end_state_path(const std::string& archive_path, std::int64_t id);
/// The checkpoint of a done replica of a rate ladder that runs again to make its lost end
/// state (ARCHIVE.checkpoints/rebuild_<id>.h5): a long rebuild interrupted goes on from it.
std::string rebuild_state_path(const std::string& archive_path, std::int64_t id);

/// The configuration saved in a checkpoint or end-state file (format checked only).
System read_state_system(const std::string& path);
/// The same, its body checked against a replica with parameters `p` (N disks, finite values,
/// checksum); throws CheckpointError naming the file and what is wrong.
System read_state_system(const std::string& path, const ReplicaParams& p);

/// Write `state` of the replica with parameters `p` (atomically: tmp, fsync, rename). A
/// `final` checkpoint is the last checkpoint step of a finished replica, kept so that a
/// longer run of it (an extended campaign) continues from there; it is not fsynced (losing
/// it costs only the recomputation).
void write_checkpoint(const std::string& path, const ReplicaParams& p, const ReplicaState& state, bool final = false);

/// Read a checkpoint and check that it belongs to a replica with parameters `p` (up to the
/// run length, which may have grown) written by this version's checkpoint format, at a step
/// within the replica's run, and that its body is whole: every particle array N long, finite
/// values, and the checksum over its contents (files written since it was kept) the same as
/// at writing; throws CheckpointError otherwise.
ReplicaState read_checkpoint(const std::string& path, const ReplicaParams& p);

}  // namespace jamsim
