#include "jamsim/archive/archive.hpp"

#include "archive_detail.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <functional>
#include <chrono>
#include <cmath>
#include <ctime>
#include <exception>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include "jamsim/core/version.hpp"
#include "jamsim/io/read_deadline.hpp"
#include "jamsim/observe/velocity_correlation.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

using archive_detail::kReasonLength;
using archive_detail::write_block;
using h5::check;
using h5::Handle;

namespace {

/// The file name of an open HDF5 file.
std::string path_of(hid_t file) {
    const ssize_t length = H5Fget_name(file, nullptr, 0);
    check(static_cast<herr_t>(length < 0 ? -1 : 0), "name of the archive");
    std::string path(static_cast<std::size_t>(length) + 1, '\0');
    check(static_cast<herr_t>(H5Fget_name(file, path.data(), path.size()) < 0 ? -1 : 0), "name of the archive");
    path.resize(static_cast<std::size_t>(length));
    return path;
}
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

const char* to_string(ReplicaStatus s) {
    switch (s) {
    case ReplicaStatus::Pending: return "pending";
    case ReplicaStatus::Running: return "running";
    case ReplicaStatus::Done: return "done";
    case ReplicaStatus::Failed: return "failed";
    }
    return "unknown";
}

std::string utc_now() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

Archive Archive::open(MPI_Comm comm, const std::string& path) {
    h5::quiet_errors();
    Handle file = h5::open_parallel(comm, path);
    ArchiveLayout layout;
    const Handle dxpl = h5::independent_transfer();
    layout.particle_offset =
        h5::read_all<std::int64_t>(file.get(), "/replicas/particle_offset", H5T_NATIVE_INT64, dxpl.get());
    layout.samples = h5::dataset_shape(file.get(), "/timeseries/time").at(1);
    layout.bins = h5::dataset_shape(file.get(), "/correlation/g_y").at(1);
    layout.particles = h5::dataset_shape(file.get(), "/final/x").at(0);
    if (h5::exists(file.get(), "/frames/strain")) layout.frames = h5::dataset_shape(file.get(), "/frames/strain").at(1);
    layout.has_threads = h5::exists(file.get(), "/replicas/threads");
    return Archive(std::move(file), comm, std::move(layout));
}

Archive::Fit Archive::check_existing(const std::string& path, const CampaignSpec& spec) {
    h5::quiet_errors();
    const auto refused = [](std::string why) { return Fit{Fit::Kind::Refused, std::move(why)}; };
    if (H5Fis_hdf5(path.c_str()) <= 0) return refused("'" + path + "' exists but is not an HDF5 file");
    try {
        const Handle file = h5::open_unlocked_readonly(path);
        const std::string stored = h5::read_string_attribute(file.get(), "spec_fingerprint");
        if (stored.empty()) return refused("'" + path + "' is not a jamsim campaign archive");
        const std::string wanted = fingerprint(spec);
        if (stored == wanted) return {};
        // Name the first difference for the person reading the message.
        std::istringstream a(stored), b(wanted);
        std::string la, lb;
        std::getline(a, la);
        std::getline(b, lb);
        // The first line is "jamsim campaign vK <name> replicas N": the same campaign from a
        // version whose results mean something else cannot be resumed or merged.
        const auto split_version = [](const std::string& line) {
            const std::string_view prefix = "jamsim campaign v";
            const std::size_t end = std::min(line.size(), line.find(' ', prefix.size()));
            return std::pair{line.substr(0, end), line.substr(end)};
        };
        // Another fingerprint version means results that mean something else (v5: random
        // numbers keyed by the replica's identity), whatever the campaign.
        const auto version_a = split_version(la).first, version_b = split_version(lb).first;
        if (version_a != version_b)
            return refused("'" + path + "' was written by another version of jamsim (" + version_a +
                           "; this one writes " + version_b + "): start a new archive");
        while (la == lb && std::getline(a, la) && std::getline(b, lb)) {}
        return {Fit::Kind::OtherCampaign,
                "'" + path + "' belongs to a different campaign (archive: \"" + la + "\", this spec: \"" + lb + "\")"};
    } catch (const h5::Error& e) { return refused("'" + path + "' cannot be read as a campaign archive: " + e.what()); }
}

Archive::Archive(h5::Handle file, MPI_Comm comm, ArchiveLayout layout)
    : file_(std::move(file)), comm_(comm), layout_(std::move(layout)) {
    struct stat st {};
    if (::stat(path_of(file_.get()).c_str(), &st) == 0) {
        device_ = static_cast<std::uint64_t>(st.st_dev);
        inode_ = static_cast<std::uint64_t>(st.st_ino);
    }
}

void Archive::check_same_file(const char* when, int descriptor) const {
    const std::string path = path_of(file_.get());
    struct stat st {};
    const bool found = descriptor >= 0 ? ::fstat(descriptor, &st) == 0 : ::stat(path.c_str(), &st) == 0;
    if (found && static_cast<std::uint64_t>(st.st_dev) == device_ && static_cast<std::uint64_t>(st.st_ino) == inode_)
        return;
    throw h5::Error("'" + path + "' is no longer the archive this run writes (it was replaced, moved or removed " +
                    "while the run wrote it), found " + when +
                    ": this run's results since it started went into the file that was there; nothing more is "
                    "written to '" +
                    path +
                    "'. Put the campaign's archive back and run the same command again (finished replicas continue "
                    "from their checkpoints)");
}

namespace {
/// `reason` in at most `bytes` bytes: a longer one is cut at a word's end and marked " ..."
/// (it was cut mid-word, "... or use a prec"), never inside a UTF-8 character.
std::string reason_to_fit(const std::string& reason, std::size_t bytes) {
    if (reason.size() <= bytes) return reason;
    const std::string mark = " ...";
    std::size_t end = bytes - mark.size();
    while (end > 0 && (static_cast<unsigned char>(reason[end]) & 0xC0) == 0x80) --end;  // a character's start
    if (const std::size_t space = reason.rfind(' ', end); space != std::string::npos && space > end / 2) end = space;
    return reason.substr(0, end) + mark;
}
}  // namespace

void Archive::clear_rows(std::int64_t replica) {
    const std::vector<double> none(layout_.samples, kNaN);
    for (const auto& c : kSampleColumns)
        write_block(file_.get(), std::string("/timeseries/") + c.name, H5T_NATIVE_DOUBLE,
                    {static_cast<hsize_t>(replica), 0}, {1, layout_.samples}, none.data());
    if (layout_.frames > 0) {
        const std::vector<double> no_frames(layout_.frames, kNaN);
        for (const char* path : {"/frames/strain", "/frames/box_strain"})
            write_block(file_.get(), path, H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(replica), 0}, {1, layout_.frames},
                        no_frames.data());
    }
}

void Archive::write_frame(std::int64_t replica, std::int64_t index, double strain, const FinalConfiguration& frame) {
    const WriteDeadline deadline(path_of(file_.get()),
                                 "replica " + std::to_string(replica) + "'s frame " + std::to_string(index),
                                 mpi::rank(comm_), write_deadline_seconds());
    const auto r = static_cast<hsize_t>(replica);
    const auto k = static_cast<hsize_t>(index);
    if (k >= layout_.frames)
        throw h5::Error("replica " + std::to_string(replica) + ": frame " + std::to_string(index) +
                        " beyond the archive's " + std::to_string(layout_.frames) + " frames");
    const auto n = static_cast<hsize_t>(frame.x.size());
    const auto first = static_cast<hsize_t>(layout_.particle_offset.at(r));
    const hid_t f = file_.get();
    write_block(f, "/frames/x", H5T_NATIVE_DOUBLE, {k, first}, {1, n}, frame.x.data());
    write_block(f, "/frames/y", H5T_NATIVE_DOUBLE, {k, first}, {1, n}, frame.y.data());
    write_block(f, "/frames/box_strain", H5T_NATIVE_DOUBLE, {r, k}, {1, 1}, &frame.box_strain);
    write_block(f, "/frames/strain", H5T_NATIVE_DOUBLE, {r, k}, {1, 1}, &strain);  // last: marks it
}

void Archive::mark_running(std::int64_t replica, int rank, bool keep_rows) {
    const WriteDeadline deadline(path_of(file_.get()), "replica " + std::to_string(replica) + "'s start",
                                 mpi::rank(comm_), write_deadline_seconds());
    const auto r = static_cast<hsize_t>(replica);
    const std::int32_t who = rank;
    write_block(file_.get(), "/replicas/rank", H5T_NATIVE_INT32, {r}, {1}, &who);
    // Its rows NaN until written (the datasets are not filled): partial rows of a running
    // replica end in NaN, as finished rows do past n_samples.
    if (!keep_rows) { clear_rows(replica); }
    if (layout_.has_threads) {  // a run again (extended, retried): its threads are those of the new run
        const double none = 0.0;
        write_block(file_.get(), "/replicas/threads", H5T_NATIVE_DOUBLE, {r}, {1}, &none);
    }
    const auto s = static_cast<std::int8_t>(ReplicaStatus::Running);
    write_block(file_.get(), "/replicas/status", H5T_NATIVE_INT8, {r}, {1}, &s);
    // A replica run again (--retry-failed) forgets an old failure; after the status, so that
    // an interruption in between never leaves a failed replica without its reason.
    const char no_reason[kReasonLength] = {};
    const Handle rt = h5::fixed_string_type(kReasonLength);
    write_block(file_.get(), "/replicas/failure_reason", rt.get(), {r}, {1}, no_reason);
}

void Archive::write_done(std::int64_t replica, const ReplicaResult& result, int rank, double threads) {
    const WriteDeadline deadline(path_of(file_.get()), "replica " + std::to_string(replica) + "'s results",
                                 mpi::rank(comm_), write_deadline_seconds());
    const hid_t f = file_.get();
    const auto r = static_cast<hsize_t>(replica);
    const auto rows = static_cast<hsize_t>(result.series.size());
    // Whole rows, NaN past the replica's own length (the datasets are not filled).
    const auto padded = [](std::vector<double> v, hsize_t length) {
        v.resize(std::max<std::size_t>(v.size(), length), kNaN);
        return v;
    };
    if (rows > layout_.samples)
        throw h5::Error("replica " + std::to_string(replica) + " has more rows than its archive");
    for (const auto& c : kSampleColumns)
        write_block(f, std::string("/timeseries/") + c.name, H5T_NATIVE_DOUBLE, {r, 0}, {1, layout_.samples},
                    padded(result.series.column(c.member), layout_.samples).data());
    const FinalConfiguration fin = final_configuration(result.final_state);
    const auto n = static_cast<hsize_t>(fin.x.size());
    const auto first = static_cast<hsize_t>(layout_.particle_offset.at(r));
    write_block(f, "/final/x", H5T_NATIVE_DOUBLE, {first}, {n}, fin.x.data());
    write_block(f, "/final/y", H5T_NATIVE_DOUBLE, {first}, {n}, fin.y.data());
    write_block(f, "/final/diameter", H5T_NATIVE_DOUBLE, {first}, {n}, fin.diameter.data());
    write_block(f, "/final/box_side", H5T_NATIVE_DOUBLE, {r}, {1}, &fin.box_side);
    write_block(f, "/correlation/x", H5T_NATIVE_DOUBLE, {r, 0}, {1, layout_.bins},
                padded(result.correlation_x, layout_.bins).data());
    write_block(f, "/correlation/g_y", H5T_NATIVE_DOUBLE, {r, 0}, {1, layout_.bins},
                padded(result.correlation_g, layout_.bins).data());
    write_block(f, "/final/box_strain", H5T_NATIVE_DOUBLE, {r}, {1}, &fin.box_strain);
    write_block(f, "/replicas/wall_seconds", H5T_NATIVE_DOUBLE, {r}, {1}, &result.wall_seconds);
    const auto rows_written = static_cast<std::int64_t>(rows);
    const double complete = 1.0;
    write_block(f, "/replicas/rows_written", H5T_NATIVE_INT64, {r}, {1}, &rows_written);
    write_block(f, "/replicas/progress", H5T_NATIVE_DOUBLE, {r}, {1}, &complete);
    write_block(f, "/replicas/force_evaluations", H5T_NATIVE_INT64, {r}, {1}, &result.force_evaluations);
    const std::int32_t who = rank;
    write_block(f, "/replicas/rank", H5T_NATIVE_INT32, {r}, {1}, &who);
    if (layout_.has_threads)  // not in archives made before the column existed
        write_block(f, "/replicas/threads", H5T_NATIVE_DOUBLE, {r}, {1}, &threads);
    // Last: the flag that makes the rows above valid; after them on the disk too (a node's
    // crash or power loss writes the page cache back in any order).
    sync_data();
    const auto s = static_cast<std::int8_t>(ReplicaStatus::Done);
    write_block(f, "/replicas/status", H5T_NATIVE_INT8, {r}, {1}, &s);
}

void Archive::write_progress(std::int64_t replica, const TimeSeries& series, std::size_t from_row, double progress) {
    const WriteDeadline deadline(path_of(file_.get()), "replica " + std::to_string(replica) + "'s rows so far",
                                 mpi::rank(comm_), write_deadline_seconds());
    const hid_t f = file_.get();
    const auto r = static_cast<hsize_t>(replica);
    const auto rows = static_cast<hsize_t>(series.size());
    const auto first = static_cast<hsize_t>(std::min(from_row, series.size()));
    if (rows > first)
        for (const auto& c : kSampleColumns) {
            const std::vector<double> column = series.column(c.member);
            write_block(f, std::string("/timeseries/") + c.name, H5T_NATIVE_DOUBLE, {r, first}, {1, rows - first},
                        column.data() + first);
        }
    const auto rows_written = static_cast<std::int64_t>(rows);
    write_block(f, "/replicas/rows_written", H5T_NATIVE_INT64, {r}, {1}, &rows_written);
    write_block(f, "/replicas/progress", H5T_NATIVE_DOUBLE, {r}, {1}, &progress);
}

void Archive::write_failed(std::int64_t replica, const std::string& reason, double wall_seconds, int rank) {
    const WriteDeadline deadline(path_of(file_.get()), "replica " + std::to_string(replica) + "'s failure",
                                 mpi::rank(comm_), write_deadline_seconds());
    const hid_t f = file_.get();
    const auto r = static_cast<hsize_t>(replica);
    // Its rows: NaN (the datasets are not filled, and a reader may ignore the status).
    clear_rows(replica);
    char text[kReasonLength] = {};
    reason_to_fit(reason, kReasonLength - 1).copy(text, kReasonLength - 1);
    const Handle rt = h5::fixed_string_type(kReasonLength);
    write_block(f, "/replicas/failure_reason", rt.get(), {r}, {1}, text);
    write_block(f, "/replicas/wall_seconds", H5T_NATIVE_DOUBLE, {r}, {1}, &wall_seconds);
    const std::int32_t who = rank;
    write_block(f, "/replicas/rank", H5T_NATIVE_INT32, {r}, {1}, &who);
    const auto s = static_cast<std::int8_t>(ReplicaStatus::Failed);
    write_block(f, "/replicas/status", H5T_NATIVE_INT8, {r}, {1}, &s);
}

void Archive::import_replica(const std::string& source_path, std::int64_t replica) {
    import_replica(source_path, replica, replica);
}

void Archive::import_replica(const std::string& source_path, std::int64_t source_replica, std::int64_t replica) {
    const Handle src = h5::open_unlocked_readonly(source_path);
    const auto from = static_cast<hsize_t>(source_replica);
    const auto r = static_cast<hsize_t>(replica);
    // Everything that belongs to one replica; its parameters are the same by its identity.
    std::vector<std::string> paths;
    for (const auto& c : kSampleColumns) paths.push_back(std::string("/timeseries/") + c.name);
    for (const char* p :
         {"/correlation/x", "/correlation/g_y", "/final/box_side", "/final/box_strain", "/replicas/rank",
          "/replicas/wall_seconds", "/replicas/force_evaluations", "/replicas/rows_written", "/replicas/progress",
          "/replicas/failure_reason", "/replicas/status"})  // status last: it validates the rest
        paths.emplace_back(p);
    for (const char* p :
         {"/replicas/initial_state", "/replicas/initial_source", "/replicas/threads"})  // where both have them
        if (h5::exists(src.get(), p) && h5::exists(file_.get(), p))
            paths.insert(paths.end() - 1, p);  // before the status
    // The final configuration: its N disks, at the replica's offset in each archive.
    {
        const auto first = static_cast<hsize_t>(layout_.particle_offset.at(r));
        const hsize_t n = (r + 1 < layout_.particle_offset.size() ? static_cast<hsize_t>(layout_.particle_offset[r + 1])
                                                                  : layout_.particles) -
                          first;
        std::int64_t source_first = 0;
        h5::read_block(src.get(), "/replicas/particle_offset", H5T_NATIVE_INT64, {from}, {1}, &source_first);
        std::vector<double> buffer(n);
        for (const char* path : {"/final/x", "/final/y", "/final/diameter"}) {
            h5::read_block(src.get(), path, H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(source_first)}, {n},
                           buffer.data());
            write_block(file_.get(), path, H5T_NATIVE_DOUBLE, {first}, {n}, buffer.data());
        }
    }
    // Configuration frames (the source's frames that fit this archive's rows; a longer run's
    // further frames come from its continuation).
    if (layout_.frames > 0 && h5::exists(src.get(), "/frames/strain")) {
        const auto first = static_cast<hsize_t>(layout_.particle_offset.at(r));
        std::int64_t source_first = 0;
        h5::read_block(src.get(), "/replicas/particle_offset", H5T_NATIVE_INT64, {from}, {1}, &source_first);
        const hsize_t source_frames = h5::dataset_shape(src.get(), "/frames/strain").at(1);
        const hsize_t common = std::min(source_frames, layout_.frames);
        std::vector<double> strains(source_frames), boxes(source_frames);
        h5::read_block(src.get(), "/frames/strain", H5T_NATIVE_DOUBLE, {from, 0}, {1, source_frames}, strains.data());
        h5::read_block(src.get(), "/frames/box_strain", H5T_NATIVE_DOUBLE, {from, 0}, {1, source_frames}, boxes.data());
        const hsize_t n = (r + 1 < layout_.particle_offset.size() ? static_cast<hsize_t>(layout_.particle_offset[r + 1])
                                                                  : layout_.particles) -
                          first;
        std::vector<double> buffer(n);
        for (hsize_t k = 0; k < common; ++k) {
            if (std::isnan(strains[k])) continue;
            for (const char* path : {"/frames/x", "/frames/y"}) {
                h5::read_block(src.get(), path, H5T_NATIVE_DOUBLE, {k, static_cast<hsize_t>(source_first)}, {1, n},
                               buffer.data());
                write_block(file_.get(), path, H5T_NATIVE_DOUBLE, {k, first}, {1, n}, buffer.data());
            }
        }
        strains.resize(layout_.frames, kNaN);
        boxes.resize(layout_.frames, kNaN);
        std::fill(strains.begin() + static_cast<std::ptrdiff_t>(common), strains.end(), kNaN);
        std::fill(boxes.begin() + static_cast<std::ptrdiff_t>(common), boxes.end(), kNaN);
        write_block(file_.get(), "/frames/box_strain", H5T_NATIVE_DOUBLE, {r, 0}, {1, layout_.frames}, boxes.data());
        write_block(file_.get(), "/frames/strain", H5T_NATIVE_DOUBLE, {r, 0}, {1, layout_.frames}, strains.data());
    }
    for (const auto& path : paths) {
        const std::vector<hsize_t> dims = h5::dataset_shape(src.get(), path);
        if (dims.size() == 2) {  // a row (doubles): its length follows each campaign's longest replica
            const hsize_t length = path.rfind("/timeseries/", 0) == 0 ? layout_.samples : layout_.bins;
            const hsize_t common = std::min(length, dims[1]);
            std::vector<double> row(std::max(length, dims[1]), kNaN);
            h5::read_block(src.get(), path, H5T_NATIVE_DOUBLE, {from, 0}, {1, dims[1]}, row.data());
            // Past this replica's own length both archives hold NaN; a longer source row ends in it.
            std::fill(row.begin() + static_cast<std::ptrdiff_t>(common), row.end(), kNaN);
            write_block(file_.get(), path, H5T_NATIVE_DOUBLE, {r, 0}, {1, length}, row.data());
            continue;
        }
        Handle set(H5Dopen2(src.get(), path.c_str(), H5P_DEFAULT), H5Dclose, "open " + path);
        Handle stored(H5Dget_type(set.get()), H5Tclose, "type of " + path);
        Handle type(H5Tget_native_type(stored.get(), H5T_DIR_DEFAULT), H5Tclose, "native type");
        std::vector<unsigned char> buffer(H5Tget_size(type.get()));
        h5::read_block(src.get(), path, type.get(), {from}, {1}, buffer.data());
        write_block(file_.get(), path, type.get(), {r}, {1}, buffer.data());
    }
}

std::vector<ReplicaStatus> Archive::read_status() const {
    const Handle dxpl = h5::independent_transfer();
    const auto raw = h5::read_all<std::int8_t>(file_.get(), "/replicas/status", H5T_NATIVE_INT8, dxpl.get());
    std::vector<ReplicaStatus> out;
    for (auto v : raw) out.push_back(static_cast<ReplicaStatus>(v));
    return out;
}

FinalConfiguration Archive::read_final(std::int64_t replica, std::size_t n) const {
    const Handle dxpl = h5::independent_transfer();
    const hid_t f = file_.get();
    const auto r = static_cast<hsize_t>(replica);
    const auto first = static_cast<hsize_t>(layout_.particle_offset.at(r));
    FinalConfiguration fin{
        .x = std::vector<double>(n), .y = std::vector<double>(n), .diameter = std::vector<double>(n)};
    h5::read_block(f, "/final/x", H5T_NATIVE_DOUBLE, {first}, {n}, fin.x.data(), dxpl.get());
    h5::read_block(f, "/final/y", H5T_NATIVE_DOUBLE, {first}, {n}, fin.y.data(), dxpl.get());
    h5::read_block(f, "/final/diameter", H5T_NATIVE_DOUBLE, {first}, {n}, fin.diameter.data(), dxpl.get());
    h5::read_block(f, "/final/box_side", H5T_NATIVE_DOUBLE, {r}, {1}, &fin.box_side, dxpl.get());
    h5::read_block(f, "/final/box_strain", H5T_NATIVE_DOUBLE, {r}, {1}, &fin.box_strain, dxpl.get());
    return fin;
}

void Archive::stamp(const std::string& attribute) {
    // Collective: a write that fails on one rank leaves the others waiting (read_deadline.hpp).
    const WriteDeadline deadline(path_of(file_.get()), "the stamp '" + attribute + "'", mpi::rank(comm_),
                                 write_deadline_seconds());
    check_same_file("at the stamp");
    std::string now = utc_now();
    mpi::broadcast(now, 0, comm_);
    // Metadata changes are collective, and HDF5 needs every rank's metadata cache to take
    // the same path through them. The independent writes of a run (each rank opens the
    // datasets of its own replicas) leave the caches different, which deadlocked this very
    // attribute write with 64 ranks and 10^4 replicas; closing and reopening the file makes
    // them the same (empty) first.
    {
        const std::string path = path_of(file_.get());
        file_.close("archive '" + path + "'");
        file_ = h5::open_parallel(comm_, path);
    }
    const hid_t f = file_.get();
    // Written over where they stand (made so at creation): nothing new is allocated, so a
    // write that fails on one rank here cannot leave the file shorter than its superblock
    // says, which HDF5 refuses to open ever after.
    h5::overwrite_attribute(f, attribute, now);
    h5::overwrite_attribute(f, "n_ranks", static_cast<std::int64_t>(mpi::size(comm_)));
    check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush archive");
}

void Archive::sync_data() const {
    const std::string path = path_of(file_.get());
    const int descriptor = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    // fdatasync through any descriptor writes back the file's pages that this node holds.
    const bool synced = descriptor >= 0 && ::fdatasync(descriptor) == 0;
    const int error = errno;
    struct Closer {
        int fd;
        ~Closer() {
            if (fd >= 0) ::close(fd);
        }
    } const closer{descriptor};
    if (!synced) throw h5::Error("writing '" + path + "' to its disk (fdatasync) failed: " + std::strerror(error));
    check_same_file("at a replica's write", descriptor);  // a file at the path, but another one
}

void Archive::close() {
    if (!file_.get()) return;
    const WriteDeadline deadline(path_of(file_.get()), "its close", mpi::rank(comm_), write_deadline_seconds());
    file_.close("archive");
}

Archive::~Archive() {
    if (std::uncaught_exceptions() > 0) file_.abandon();
}

}  // namespace jamsim
