#include "jamsim/archive/capacity.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/core/memory.hpp"
#include "jamsim/io/read_deadline.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Peak memory of a rank before it runs a replica: MPI, HDF5, PETSc (measured ~35 MB).
constexpr double kLibraryBytes = 64e6;
/// Free space left on the filesystem after the campaign (a full disk breaks everyone's jobs).
constexpr double kDiskMargin = 0.10;
/// An archive's bytes beyond its datasets' (HDF5's superblock, object headers, chunk indexes,
/// attributes, the campaign text): about twice the 44-56 kB that finished archives of 1 to 18
/// replicas had beyond archive_layout()'s bytes (tests/data/campaigns other_campaign, small,
/// frames, static_small). It was 1 MB, which made a 56 kB archive's estimate 1 MB.
constexpr double kArchiveMetadataBytes = 128e3;

}  // namespace

double free_bytes(const std::string& output) {
    namespace fs = std::filesystem;
    const fs::path p(output);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    struct statvfs s {};
    if (::statvfs(dir.c_str(), &s) != 0) return kNaN;
    return static_cast<double>(s.f_bavail) * static_cast<double>(s.f_frsize);
}

bool disk_full(const std::string& path) {
    const double free = free_bytes(path);
    return std::isfinite(free) && free < 1e6;
}

namespace {

/// A file to test a write in, beside `path`: nameless (O_TMPFILE, gone when closed) where the
/// filesystem allows, else named by host and process (ranks on several nodes test at once).
/// -1 with errno when it cannot be made.
int test_file(const std::string& path, std::string& named) {
    const std::filesystem::path p(path);
    const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
    const int fd = ::open(dir.c_str(), O_WRONLY | O_TMPFILE | O_CLOEXEC, 0600);
    if (fd >= 0 || (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)) return fd;
    char host[64] = "host";
    (void)::gethostname(host, sizeof host - 1);
    named = path + "." + host + "." + std::to_string(::getpid()) + ".write-test";
    return ::open(named.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
}

}  // namespace

std::string write_refused(const std::string& path) {
    if (disk_full(path)) return kNoSpaceLeft;
    // A filesystem that hangs rather than refuses must not hold the rank from its abort.
    const double seconds = write_deadline_seconds();
    const Deadline watch("jamsim: a test write beside '" + path + "' did not finish within " +
                             std::to_string(static_cast<int>(seconds)) + " s: the filesystem stopped answering",
                         seconds, 1);
    std::string named;
    int error = 0;
    const int fd = test_file(path, named);
    if (fd < 0) {
        error = errno;
        if (error == EEXIST || error == ENAMETOOLONG) return "";  // says nothing of the filesystem
    } else {
        const std::vector<char> block(std::size_t{1} << 16, '\0');
        const ssize_t written = ::write(fd, block.data(), block.size());
        if (written != static_cast<ssize_t>(block.size()))
            error = written < 0 ? errno : ENOSPC;  // a short write: the device is full
        else if (::fsync(fd) != 0)
            error = errno;
        ::close(fd);
        if (!named.empty()) ::unlink(named.c_str());
    }
    if (error == 0) return "";
    std::string why = std::strerror(error);
    if (!why.empty()) why[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(why[0])));
    return why;
}

namespace {

double occupied(const std::string& path) {
    struct stat s {};
    if (::stat(path.c_str(), &s) != 0) return 0.0;
    return static_cast<double>(s.st_blocks) * 512.0;  // allocated, not apparent (sparse) size
}

/// One checkpoint file of replica p: its particle arrays (7 doubles and a tag per disk), its
/// rows and g_y sums.
double checkpoint_size(const ReplicaParams& p) {
    const double row = 8.0 * static_cast<double>(std::size(kSampleColumns));
    return 60.0 * static_cast<double>(p.n) + row * static_cast<double>(sample_count(p)) + 4096.0;
}

}  // namespace

CapacityEstimate estimate_capacity(const CampaignSpec& spec, const std::string& output, int ranks, int ranks_per_node) {
    CapacityEstimate e;
    const ArchiveLayout layout = archive_layout(spec);
    e.archive_bytes = layout.bytes + kArchiveMetadataBytes;
    e.frame_bytes = layout.frame_bytes;
    e.frames = static_cast<double>(layout.frames);
    e.archive_present = occupied(output);
    double largest_checkpoint = 0, finals = 0, largest_replica = 0;
    for (const auto& p : spec.replicas) {
        largest_checkpoint = std::max(largest_checkpoint, checkpoint_size(p));
        largest_replica = std::max(largest_replica, estimated_memory(p));
        // A finished replica that a longer run can continue keeps its last checkpoint.
        if (model_of(p).extendable && checkpointed_steps(p) >= p.checkpoint_steps) finals += checkpoint_size(p);
    }
    const double running = std::min<double>(std::max(ranks, 1), static_cast<double>(spec.replicas.size()));
    e.checkpoint_bytes = finals + 2.0 * running * largest_checkpoint;  // a .tmp beside each
    e.free_bytes = free_bytes(output);
    e.ranks_per_node = std::max(ranks_per_node, 1);
    e.rank_memory = kLibraryBytes + static_cast<double>(spec.replicas.size()) * 1024.0 +
                    static_cast<double>(spec.text.size()) + largest_replica;
    e.node_memory = available_memory();
    return e;
}

std::string check_capacity(const CapacityEstimate& e, const CapacityLimits& limits, const CampaignSpec& spec,
                           const std::string& output) {
    std::int64_t largest_n = 0, most_samples = 0;
    for (const auto& p : spec.replicas) {
        largest_n = std::max(largest_n, p.n);
        most_samples = std::max(most_samples, sample_count(p));
    }
    const std::string shape = std::to_string(spec.replicas.size()) + " replicas, N up to " + std::to_string(largest_n) +
                              ", up to " + std::to_string(most_samples) + " samples each";
    if (e.archive_bytes > limits.max_archive_bytes)
        return spec.path + ": the archive '" + output + "' would take " + show_bytes(e.archive_bytes) + " (" + shape +
               "), more than the cap of " + show_bytes(limits.max_archive_bytes) +
               ": check N, seeds, strain and sample_interval, or raise the cap with --max-archive-size";
    const double needed =
        (e.beside_old ? e.archive_bytes : std::max(0.0, e.archive_bytes - e.archive_present)) + e.checkpoint_bytes;
    if (std::isfinite(e.free_bytes) && needed > (1.0 - kDiskMargin) * e.free_bytes)
        return spec.path + ": the archive '" + output + "' needs " + show_bytes(needed) + " more (" +
               show_bytes(e.archive_bytes) + " of archive for " + shape +
               (e.beside_old ? ", written whole beside the old one before it replaces it" : "") + ", " +
               show_bytes(e.checkpoint_bytes) + " of checkpoints), but its filesystem has " + show_bytes(e.free_bytes) +
               " free (jamsim leaves 10% of it free): write it to a larger filesystem (-o) or make the "
               "campaign smaller (fewer replicas or samples: a larger sample_interval)";
    if (std::isfinite(e.node_memory) && e.rank_memory * e.ranks_per_node > kMemoryMargin * e.node_memory)
        return spec.path + ": each rank needs about " + show_bytes(e.rank_memory) + " of memory (" + shape + "), " +
               std::to_string(e.ranks_per_node) + " ranks on this node need " +
               show_bytes(e.rank_memory * e.ranks_per_node) + ", but it has " + show_bytes(e.node_memory) +
               " available (jamsim plans for 80% of it): run fewer ranks per node or split the campaign";
    return "";
}

std::string check_replica_memory(const ReplicaParams& p) {
    const double needed = kLibraryBytes + estimated_memory(p);
    const double available = available_memory();
    if (!std::isfinite(available) || needed <= kMemoryMargin * available) return "";
    return "a replica of N = " + std::to_string(p.n) + " at phi = " + show_value(p.phi) + " needs about " +
           show_bytes(needed) + " of memory, but this node has " + show_bytes(available) +
           " available (jamsim plans for 80% of it): check N and phi, or run it on a larger node";
}

std::string check_replica_disk(const ReplicaParams& p, const std::string& output) {
    CampaignSpec one;
    one.replicas = {p};
    const double needed = archive_layout(one).bytes + kArchiveMetadataBytes;  // as a campaign's archive
    const double free = free_bytes(output);
    if (!std::isfinite(free) || needed <= (1.0 - kDiskMargin) * free) return "";
    return "the replica file '" + output + "' needs about " + show_bytes(needed) + " (N = " + std::to_string(p.n) +
           ", " + std::to_string(sample_count(p)) + " samples), but its filesystem has " + show_bytes(free) +
           " free (jamsim leaves 10% of it free): write it to a larger filesystem (-o) or take fewer samples (a "
           "larger sample_interval)";
}

double parse_bytes(const std::string& text) {
    // Decimal only: strtod also skipped leading white space and read hexadecimal ("0x10").
    if (text.empty() || !((text[0] >= '0' && text[0] <= '9') || text[0] == '.') ||
        text.find_first_of("xX") != std::string::npos)
        return -1.0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !std::isfinite(v) || v < 0) return -1.0;
    std::string unit(end);
    if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
    const double scale = unit.empty()                 ? 1.0
                         : unit == "k" || unit == "K" ? 1e3
                         : unit == "M"                ? 1e6
                         : unit == "G"                ? 1e9
                         : unit == "T"                ? 1e12
                         : unit == "P"                ? 1e15
                                                      : -1.0;
    // A size beyond a double (1e300T) is no cap at all, and one below a byte none either.
    return scale < 0 || !std::isfinite(v * scale) || v * scale < 1.0 ? -1.0 : v * scale;
}

}  // namespace jamsim
