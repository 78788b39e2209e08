#include "run_one.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

namespace {

using Clock = std::chrono::steady_clock;

/// Seconds between a running replica's progress notes (each a rename of a one-line file).
constexpr double kProgressNoteSeconds = 2.0;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The checkpoint of replica `id` when it can be used; a damaged one (unreadable, arrays that
/// do not fit the replica, non-finite values, a checksum that disagrees) is removed with a
/// warning naming the file and why, and the replica starts again from its start.
std::optional<ReplicaState> usable_checkpoint(const std::string& path, const ReplicaParams& params, std::int64_t id) {
    try {
        try {
            return read_checkpoint(path, params);
        } catch (const CheckpointError&) {
            // The storage's failure is not the file's: one the system cannot open or read (no
            // descriptors left, an I/O error, a stale mount) stops the run with the file kept
            // (run_one), and a read that failed once is tried again before the file is taken
            // for damaged. It used to be removed, and the replica to start again from its start.
            char head[8];
            const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
            const bool readable = fd >= 0 && ::read(fd, head, sizeof head) >= 0;
            const int error = errno;
            if (fd >= 0) ::close(fd);
            if (!readable)
                throw std::filesystem::filesystem_error("cannot read the checkpoint", path,
                                                        std::error_code(error, std::generic_category()));
            return read_checkpoint(path, params);
        }
    } catch (const CheckpointError& e) {
        std::fprintf(stderr, "jamsim run: warning: %s; replica %lld starts again from its start\n", e.what(),
                     static_cast<long long>(id));
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
        return std::nullopt;
    }
}

/// The kernel's threads over a replica's run, weighted by time: lending changes them only in
/// the farm's calls between samples, so they are read there.
class ThreadUse {
  public:
    /// At a sample: the threads from here on (those before it counted until now).
    void now_on(int threads) {
        const Clock::time_point now = Clock::now();
        const double dt = std::chrono::duration<double>(now - since_).count();
        thread_seconds_ += dt * threads_;
        seconds_ += dt;
        since_ = now;
        threads_ = threads;
    }
    /// The mean threads so far.
    double mean() {
        now_on(threads_);
        return seconds_ > 0 ? thread_seconds_ / seconds_ : threads_;
    }

  private:
    Clock::time_point since_ = Clock::now();
    int threads_ = kernel_threads();
    double thread_seconds_ = 0, seconds_ = 0;
};

/// A ladder replica's end state, which its successor starts from: its final state as a
/// checkpoint at its last step.
void write_end_state(const std::string& path, const ReplicaParams& params, const System& final_state) {
    const std::int64_t steps = schedule_of(params).steps;
    write_checkpoint(path, params, ReplicaState{.step = steps, .steps = steps, .system = final_state});
}

bool same_bits(const FinalConfiguration& a, const FinalConfiguration& b) {
    const auto same = [](const std::vector<double>& u, const std::vector<double>& v) {
        return u.size() == v.size() && std::memcmp(u.data(), v.data(), u.size() * sizeof(double)) == 0;
    };
    return same(a.x, b.x) && same(a.y, b.y) && same(a.diameter, b.diameter) &&
           std::memcmp(&a.box_side, &b.box_side, sizeof(double)) == 0 &&
           std::memcmp(&a.box_strain, &b.box_strain, sizeof(double)) == 0;
}

/// The start of ladder replica `successor`: the end state of its predecessor `id` (done), read
/// with the successor's parameters `params`. Its file is removed once the successor is done,
/// and a merge or a copied archive leaves it behind; when it is missing, the chain up to `id`
/// runs again from its start, as it ran (with the intermediate end states read back from their
/// files, as the successors read them), must end on the final configuration that the archive
/// holds for `id`, bitwise, and its end state is saved where the successor looks for it.
/// Throws ReplicaInterrupted when `stop` asks (the end states made so far are kept, and the
/// state of the replica being made again, in rebuild_state_path).
System ladder_start(const CampaignSpec& spec, std::int64_t id, const ReplicaParams& params, std::int64_t successor,
                    const Archive& archive, const FarmOptions& options, const std::function<void()>& between,
                    const std::function<bool()>& stop) {
    namespace fs = std::filesystem;
    const std::string path = end_state_path(options.archive_path, id);
    try {
        if (fs::exists(path)) return read_state_system(path, params);
    } catch (const CheckpointError& e) {  // damaged: made again, as a missing one
        std::fprintf(stderr, "jamsim run: warning: %s; it is made again\n", e.what());
        std::error_code ignored;
        fs::remove(path, ignored);
    }
    const ReplicaParams& own = spec.replicas[static_cast<std::size_t>(id)];
    const std::int64_t before = spec.predecessor[static_cast<std::size_t>(id)];
    // The rebuild saves checkpoints as any run does: interrupted (a signal, a time limit), it
    // goes on from there, so a chain that needs more than one allocation is made all the same.
    const std::string rebuild = rebuild_state_path(options.archive_path, id);
    std::optional<ReplicaState> resume;
    if (fs::exists(rebuild)) resume = usable_checkpoint(rebuild, own, id);
    std::fprintf(stderr,
                 "jamsim run: replica %lld starts from the end state of replica %lld, which '%s' no longer holds (a "
                 "merge or a copy of the archive leaves it behind): replica %lld runs again to make it%s; its data "
                 "in the archive stay as they are\n",
                 static_cast<long long>(successor), static_cast<long long>(id),
                 checkpoint_folder(options.archive_path).c_str(), static_cast<long long>(id),
                 resume ? (", from its checkpoint '" + rebuild + "'").c_str() : "");
    std::optional<System> initial;
    if (!resume && before >= 0)  // resumed, it needs not its own start
        initial = ladder_start(spec, before, own, id, archive, options, between, stop);
    else if (!resume && options.initial_states)
        initial = options.initial_states->load(own, id);
    auto last_save = Clock::now();
    const CheckpointPolicy saved{.due = [&] { return seconds_since(last_save) >= options.checkpoint_seconds; },
                                 .save =
                                     [&](const ReplicaState& state) {
                                         write_checkpoint(rebuild, own, state);
                                         last_save = Clock::now();
                                     },
                                 .stop = stop};
    const ReplicaResult result = run_replica(own, RunContext{.after_sample = [&](double) { between(); },
                                                             .checkpoints = &saved,
                                                             .resume = resume ? &*resume : nullptr,
                                                             .initial = initial ? &*initial : nullptr});
    const bool same =
        same_bits(final_configuration(result.final_state), archive.read_final(id, static_cast<std::size_t>(own.n)));
    if (!same && resume) {  // a stale checkpoint (of an earlier campaign's replica): once more from the start
        std::fprintf(stderr,
                     "jamsim run: warning: replica %lld, run again from its checkpoint '%s', did not end on its final "
                     "configuration in the archive; it runs again from its start\n",
                     static_cast<long long>(id), rebuild.c_str());
        std::error_code ec;
        fs::remove(rebuild, ec);
        if (ec)  // else the next call would resume from the same checkpoint, for ever
            throw std::runtime_error("cannot remove the stale checkpoint '" + rebuild + "': " + ec.message());
        return ladder_start(spec, id, params, successor, archive, options, between, stop);
    }
    if (!same)
        throw std::runtime_error("replica " + std::to_string(id) + ", run again to make the end state that replica " +
                                 std::to_string(successor) +
                                 " starts from, did not end on its final configuration in the archive (was the "
                                 "archive written by another build of jamsim?): run the rate ladder in a new archive");
    write_end_state(path, own, result.final_state);
    // The end state it started from was made for this run only (its successor `id` is done);
    // kept until now, so that an interrupted rebuild goes on from it.
    std::error_code ignored;
    fs::remove(rebuild, ignored);
    fs::remove(rebuild + ".tmp", ignored);
    if (before >= 0) fs::remove(end_state_path(options.archive_path, before), ignored);
    return read_state_system(path, params);
}

}  // namespace

Outcome run_one(const CampaignSpec& spec, std::int64_t id, bool has_successor, Archive& archive, int rank,
                const FarmOptions& options, const std::function<void()>& between, const std::function<bool()>& stop,
                FarmSummary& summary) {
    namespace fs = std::filesystem;
    const ReplicaParams& params = spec.replicas[static_cast<std::size_t>(id)];
    const auto t0 = Clock::now();
    double io = 0;
    auto timed = [&](auto&& f) {
        const auto a = Clock::now();
        f();
        io += seconds_since(a);
    };
    const std::string checkpoint = checkpoint_path(options.archive_path, id);
    std::optional<ReplicaState> resume;
    std::optional<System> initial;
    const std::int64_t before = spec.predecessor.empty() ? -1 : spec.predecessor[static_cast<std::size_t>(id)];
    const auto counted = [&](Outcome outcome) {  // this rank's tally of what it ran
        summary.resumed += resume ? 1 : 0;
        summary.io_seconds += io;
        ++summary.ran;
        summary.failed += outcome == Outcome::Failed;
        summary.interrupted += outcome == Outcome::Interrupted;
        return outcome;
    };
    Outcome outcome = Outcome::Done;
    try {  // preparing: a failure here fails this replica, never the campaign
        if (fs::exists(checkpoint)) timed([&] { resume = usable_checkpoint(checkpoint, params, id); });
        if (options.initial_states && !resume) timed([&] { initial = options.initial_states->load(params, id); });
        if (before >= 0 && !resume)  // a rate ladder: start where the predecessor ended
            initial = ladder_start(spec, before, params, id, archive, options, between, stop);
    } catch (const h5::Error&) { throw; } catch (const std::filesystem::filesystem_error&) {
        throw;  // the storage failed, not the replica (see below)
    } catch (const ReplicaInterrupted&) {
        return counted(Outcome::Interrupted);  // still pending
    } catch (const std::exception& e) {
        timed([&] { archive.write_failed(id, e.what(), seconds_since(t0), rank); });
        return counted(Outcome::Failed);
    }
    if (initial && options.initial_states && before < 0)  // what it starts from, for later runs to check
        timed([&] {
            archive.record_initial(id, options.initial_states->fingerprint(), InitialStates::digest(*initial));
        });
    timed([&] { archive.mark_running(id, rank, resume.has_value()); });
    const std::string note = progress_note_path(options.archive_path, id);
    auto last_note = Clock::now() - std::chrono::hours(1);
    auto last_save = Clock::now();
    std::size_t rows_saved = resume ? resume->series.size() : 0;  // already in the archive
    const CheckpointPolicy policy{
        .due = [&] { return seconds_since(last_save) >= options.checkpoint_seconds; },
        .save =
            [&](const ReplicaState& state) {
                const double done =
                    static_cast<double>(state.step) / static_cast<double>(std::max<std::int64_t>(state.steps, 1));
                timed([&] {
                    archive.sync_data();  // the frames before this state are on the disk before it
                    write_checkpoint(checkpoint, params, state);
                    archive.write_progress(id, state.series, rows_saved, done);
                    write_progress_note(note, done);  // the note never says less than the checkpoint
                });
                rows_saved = state.series.size();
                last_note = Clock::now();
                last_save = Clock::now();
            },
        .stop = stop};
    // Between samples: the farm's messages, and every kProgressNoteSeconds a note of how far
    // the replica has got (jamsim status reads it between checkpoints).
    ThreadUse threads;
    const SampleHook after_sample = [&](double done) {
        between();
        threads.now_on(kernel_threads());
        if (!std::isfinite(done) || seconds_since(last_note) < kProgressNoteSeconds) return;
        timed([&] { write_progress_note(note, done); });
        last_note = Clock::now();
    };
    std::shared_ptr<const ReplicaState> last_checkpoint;
    try {
        const ReplicaResult result =
            run_replica(params, RunContext{.after_sample = after_sample,
                                           // Each frame straight into its place in the archive: frames
                                           // before a checkpoint are there before the checkpoint is saved.
                                           .on_frame =
                                               [&](std::int64_t k, double strain, const FinalConfiguration& frame) {
                                                   timed([&] { archive.write_frame(id, k, strain, frame); });
                                               },
                                           .checkpoints = &policy,
                                           .resume = resume ? &*resume : nullptr,
                                           .initial = initial ? &*initial : nullptr});
        if (has_successor)  // durable before the status that lets the successor start
            timed([&] { write_end_state(end_state_path(options.archive_path, id), params, result.final_state); });
        timed([&] { archive.write_done(id, result, rank, threads.mean()); });
        last_checkpoint = result.last_checkpoint;
        std::error_code ignored;
        fs::remove(rebuild_state_path(options.archive_path, id), ignored);  // a rebuild's, stale now
        if (before >= 0)                                                    // the predecessor's end state has served
            fs::remove(end_state_path(options.archive_path, before), ignored);
    } catch (const h5::Error&) {
        throw;  // the archive itself is broken: stop
    } catch (const std::filesystem::filesystem_error&) {
        // A checkpoint, end state or note that the filesystem refused (a failed rename or
        // mkdir: a read-only filesystem, a quota) is the storage's failure, not the replica's:
        // stop with its checkpoint kept, as a failed write of the archive does. It used to mark
        // the replica failed for good and remove its last good checkpoint.
        throw;
    } catch (const ReplicaInterrupted&) {
        outcome = Outcome::Interrupted;  // its state is saved; status stays "running"
    } catch (const std::exception& e) {
        outcome = Outcome::Failed;
        timed([&] { archive.write_failed(id, e.what(), seconds_since(t0), rank); });
    }
    if (outcome != Outcome::Interrupted) {  // finished: its checkpoint (and a .tmp left by a
        std::error_code ignored;            // kill during a write) is stale now
        fs::remove(checkpoint, ignored);
        fs::remove(checkpoint + ".tmp", ignored);
        fs::remove(note, ignored);
        fs::remove(note + ".tmp", ignored);
    }
    if (outcome == Outcome::Done && last_checkpoint && model_of(params).extendable) {  // a longer run continues from it
        try {
            timed([&] { write_checkpoint(checkpoint, params, *last_checkpoint, true); });
        } catch (const std::exception& e) {  // the replica is done and whole: only an extension's shortcut is lost
            std::fprintf(stderr,
                         "jamsim run: warning: replica %lld is done, but its final checkpoint could not be written "
                         "(%s): an extension of the campaign runs it again from its start\n",
                         static_cast<long long>(id), e.what());
        }
    }
    return counted(outcome);
}

}  // namespace jamsim
