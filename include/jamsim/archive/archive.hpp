#pragma once
#include <mpi.h>

#include <limits>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "jamsim/run/replica.hpp"
#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/io/hdf5.hpp"

namespace jamsim {

/// Replica status codes stored in /replicas/status.
enum class ReplicaStatus : std::int8_t { Pending = 0, Running = 1, Done = 2, Failed = 3 };
const char* to_string(ReplicaStatus s);

/// The shapes of a campaign's archive, from its spec.
struct ArchiveLayout {
    hsize_t samples = 1;                        ///< row length of /timeseries (the most samples of any replica)
    hsize_t bins = 1;                           ///< row length of /correlation (the most g_y bins)
    hsize_t particles = 1;                      ///< length of /final/x: every replica's N (at least 1)
    std::vector<std::int64_t> particle_offset;  ///< [R] first disk of each replica in /final
    hsize_t frames = 0;                         ///< configuration frames per replica (most of any; 0: no /frames)
    double frame_bytes = 0.0;                   ///< bytes of /frames (part of `bytes`)
    bool has_threads = true;                    ///< /replicas/threads exists (not before that column)
    /// Bytes the archive will take once every replica is written (data, not metadata).
    double bytes = 0.0;
    /// One replica of N disks: its row of every per-replica dataset (time series and g_y rows
    /// as long as the campaign's longest, ~40 parameter and bookkeeping numbers, a 200-byte
    /// reason) and its configurations (configuration_bytes).
    double replica_bytes(std::int64_t n) const;
    /// Its final configuration (x, y, diameter) and frames (x, y per frame, two numbers each).
    double configuration_bytes(std::int64_t n) const;
};
ArchiveLayout archive_layout(const CampaignSpec& spec);

/// One campaign archive, opened by every rank of `comm` through the MPI-IO driver.
///
/// Crash safety by construction: create() makes every dataset collectively with its final
/// shape (early allocation; the bulk unfilled, so creation writes no data) and flushes; after that the run writes only raw data,
/// independently, into space that already exists, so no metadata changes until the
/// collective close. A replica's rows are written first and its status (done/failed) last,
/// so after a SIGKILL the status column says which rows are valid. Layout: campaigns/README.md,
/// "Campaign archive".
class Archive {
  public:
    /// Collective: new archive for `spec` (truncating `path`). PATH.creating (creation_marker)
    /// is there from before the file is made until it is flushed whole: a kill in between
    /// leaves a file without even the HDF5 signature (HDF5 writes the superblock from its
    /// cache), and the marker says that it is such a leftover, not a file of the user's.
    static Archive create(MPI_Comm comm, const std::string& path, const CampaignSpec& spec);
    static std::string creation_marker(const std::string& path) { return path + ".creating"; }
    /// Serial, before anything else uses `path` (its lock free): when its creation marker is
    /// there, removes the archive that a kill left half-made and the marker (nothing ran in
    /// it: replicas start after the creation). Returns what it did ("" when nothing).
    static std::string undo_interrupted_creation(const std::string& path);
    /// Collective: existing archive for read-write (its spec was checked with check_existing).
    static Archive open(MPI_Comm comm, const std::string& path);

    /// How an existing file stands against a spec: what callers branch on, beside the words.
    struct Fit {
        enum class Kind {
            Same,           ///< this campaign's archive
            OtherCampaign,  ///< a jamsim archive of this version, of another campaign (or a longer or grown one)
            Refused,        ///< not HDF5, not an archive, another version's, or unreadable
        };
        Kind kind = Kind::Same;
        std::string why;  ///< "" when Same; otherwise one sentence naming the file
    };
    /// Serial, read-only check of an existing file against a spec.
    static Fit check_existing(const std::string& path, const CampaignSpec& spec);

    /// Serial, read-only: "" when `spec` continues the archive's campaign to a longer run (the
    /// same replicas, each with a strain, or time at rate 0, at least as large and one larger),
    /// otherwise why not.
    static std::string check_extension(const std::string& path, const CampaignSpec& spec);
    /// Collective: rewrite the archive at `path` for the longer campaign `spec`: a new archive
    /// with room for the longer runs (written beside it, then renamed over it, so a kill leaves
    /// the old one whole) holding the failed replicas as they were and the finished ones as
    /// partial rows of running replicas, which continue from their final checkpoints. A rate
    /// ladder's later replicas are pending again: they start from their predecessor's new end
    /// state, as in the longer campaign run in one go.
    static void extend(MPI_Comm comm, const std::string& path, const CampaignSpec& spec);
    /// Serial, while no run holds the archive at `path`: remove the new archive (and its
    /// creation marker) that an extension killed before its rename left beside it. Returns
    /// what it did ("" when nothing).
    static std::string remove_interrupted_extension(const std::string& path);

    /// Serial, read-only: "" when `spec` is the archive's campaign with a sweep that differs
    /// (grown: more seeds, rates, phi or N values, points; every replica of the archive still
    /// in it), and then `source[k]` is the archive's id of spec's replica k (−1: new);
    /// otherwise why not, naming the setting that differs ("[potential] alpha: archive 2,
    /// file 2.5") or the replica the file lost.
    static std::string check_growth(const std::string& path, const CampaignSpec& spec,
                                    std::vector<std::int64_t>& source);
    /// Collective: rewrite the archive at `path` for the grown campaign `spec` (`source` from
    /// check_growth, needed on rank 0): a new archive beside it (PATH.growing) that holds every
    /// replica of the old one that has started, at its new position, and its checkpoints
    /// under their new ids (PATH.growing.checkpoints); then renamed over it, so a kill before
    /// the rename leaves the old archive and its checkpoints whole, and finish_growth completes
    /// one after it.
    static void grow(MPI_Comm comm, const std::string& path, const CampaignSpec& spec,
                     const std::vector<std::int64_t>& source);
    /// Serial, before anything else uses the archive at `path` (its lock free): complete a
    /// growth that a kill interrupted after its rename (the new checkpoint folder replaces the
    /// old), or remove what one left before it. Returns what it did ("" when nothing).
    static std::string finish_growth(const std::string& path);

    /// Independent writes, by the rank that runs the replica.
    /// Status running; its rows are set to NaN unless `keep_rows` (a replica continued from a
    /// checkpoint, whose rows so far are in the archive).
    void mark_running(std::int64_t replica, int rank, bool keep_rows = false);
    /// Its rows, final configuration and bookkeeping, then status done. `threads`: the
    /// kernel's mean threads over its run, weighted by time (/replicas/threads, where the
    /// archive has the column).
    void write_done(std::int64_t replica, const ReplicaResult& result, int rank, double threads);
    /// A running replica's rows so far and its progress (fraction of steps) at a checkpoint:
    /// readers see them while its status is still 1 (running), i.e. partial. Rows before
    /// `from_row` are in the archive already and are not written again.
    void write_progress(std::int64_t replica, const TimeSeries& series, std::size_t from_row, double progress);
    void write_failed(std::int64_t replica, const std::string& reason, double wall_seconds, int rank);
    /// What the replica starts from ([run] initial): the source's fingerprint and the state's
    /// digest (InitialStates), before its status says running. Nothing in an archive made
    /// before these columns existed.
    void record_initial(std::int64_t replica, std::uint64_t source, std::uint64_t state);
    /// Configuration frame `index` of a running replica (disks in tag order, sheared
    /// coordinates in [0, L)) and its strain (time at rate 0); valid once its status is done.
    void write_frame(std::int64_t replica, std::int64_t index, double strain, const FinalConfiguration& frame);

    /// Copy replica `replica` (its rows, final configuration, bookkeeping and, last, its
    /// status) from another archive of the same campaign, opened serially read-only.
    void import_replica(const std::string& source_path, std::int64_t replica);
    /// The same for the replica `source_replica` of another archive that holds it (the same
    /// identity: parameters and seed) at another position, as this archive's `replica`.
    void import_replica(const std::string& source_path, std::int64_t source_replica, std::int64_t replica);

    /// Serial, read-only: "" when replica `a_replica` of the archive `a` and `b_replica` of `b`
    /// (the same replica: the same identity) hold bitwise the same data (rows, g_y, final
    /// configuration, force evaluations; NaN padding past the shorter row), otherwise the
    /// first dataset that differs.
    static std::string replica_difference(const std::string& a, std::int64_t a_replica, const std::string& b,
                                          std::int64_t b_replica);

    /// Independent read of every replica's status.
    std::vector<ReplicaStatus> read_status() const;
    /// Independent read of a done replica's final configuration (`n` disks).
    FinalConfiguration read_final(std::int64_t replica, std::size_t n) const;

    /// Collective: record a time stamp attribute (e.g. run_started) and the number of ranks,
    /// then flush.
    void stamp(const std::string& attribute);
    /// Collective close.
    void close();

    Archive(Archive&&) noexcept = default;
    Archive& operator=(Archive&&) = delete;
    /// Closes the file (collective), except while an exception unwinds: then the other ranks
    /// may never reach the close, so the file is left to the abort that follows (its data
    /// were written before any status that validates them; see above).
    ~Archive();

    /// Independent: this node's writes to the archive so far onto its disk (fdatasync), so that
    /// what a status or a checkpoint vouches for survives a node's crash.
    void sync_data() const;

  private:
    Archive(h5::Handle file, MPI_Comm comm, ArchiveLayout layout);
    /// The replica's rows set to NaN (the bulk datasets are not filled).
    void clear_rows(std::int64_t replica);
    /// Throws h5::Error unless the archive's path still names the file this object opened
    /// (`descriptor`: one open on it, else the path is looked up): an archive replaced, moved
    /// or removed while a run wrote it lost the run's results into the old file, and the
    /// stamps, which reopen the path, went into the new one (another campaign's archive).
    void check_same_file(const char* when, int descriptor = -1) const;
    h5::Handle file_;
    MPI_Comm comm_ = MPI_COMM_NULL;
    ArchiveLayout layout_;
    std::uint64_t device_ = 0, inode_ = 0;  ///< of the file opened (stat), for check_same_file
};

/// /replicas/initial_source and /replicas/initial_state of an archive (serial, read-only;
/// both empty when it has none).
struct InitialRecords {
    std::vector<std::uint64_t> source, state;
};
InitialRecords read_initial_records(const std::string& path);
/// Collective, inside Archive::create: those columns, for a campaign with [run] initial.
void create_initial_columns(hid_t file, const CampaignSpec& spec);

/// Read-only summary of an archive for `jamsim status` and tests (serial driver).
struct ArchiveSummary {
    std::string campaign;
    std::string started, finished;
    std::string merged;  ///< when jamsim merge last wrote it ("" if never)
    std::int64_t pending = 0, running = 0, done = 0, failed = 0;
    double wall_seconds_done = 0.0;
    double cost_done = 0.0, cost_left = 0.0;  ///< estimated costs of done / unfinished replicas
    std::int64_t ranks = 0;                   ///< ranks of the latest run (0 if never run)
    std::vector<std::string> failures;        ///< "replica 3: reason"
    struct Progress {
        std::int64_t replica;
        double fraction;  ///< of its steps, at its last checkpoint
        /// Of its steps at its latest progress note (io/checkpoint_file.hpp, every few seconds
        /// while it runs; where an interrupted one stopped) and the note's age in seconds;
        /// NaN without a note.
        double noted = std::numeric_limits<double>::quiet_NaN();
        double note_age = std::numeric_limits<double>::quiet_NaN();
    };
    std::vector<Progress> in_progress;  ///< running (or interrupted) replicas
    /// Per replica: its wall seconds and fraction of its steps at its last checkpoint.
    std::vector<double> wall_seconds, progress;
};
ArchiveSummary summarize_archive(const std::string& path);

/// Status column and campaign spec stored in an archive (serial read-only).
struct StoredCampaign {
    CampaignSpec spec;
    std::vector<ReplicaStatus> status;
};
StoredCampaign read_stored_campaign(const std::string& path);

/// Current UTC time as ISO 8601.
std::string utc_now();

}  // namespace jamsim
