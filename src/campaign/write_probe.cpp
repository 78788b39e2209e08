// The archive's writes per replica, measured beside the output (write_probe.hpp).
#include "jamsim/campaign/write_probe.hpp"

#include <fcntl.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <random>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

namespace {
/// Up to `most` replicas of the campaign's smallest N, in the campaign's order: their writes
/// are the fixed cost (a large replica's final configuration adds bandwidth, not latency).
std::vector<ReplicaParams> smallest_replicas(const CampaignSpec& spec, std::size_t most) {
    std::int64_t smallest = spec.replicas.front().n;
    for (const ReplicaParams& p : spec.replicas) smallest = std::min(smallest, p.n);
    std::vector<ReplicaParams> out;
    for (const ReplicaParams& p : spec.replicas)
        if (p.n == smallest && out.size() < most) out.push_back(p);
    return out;
}

/// Removes the scratch archive (and a creation marker a failure left) when the probe ends.
struct ScratchFiles {
    std::string path;
    ~ScratchFiles() {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
        std::filesystem::remove(Archive::creation_marker(path), ignored);
    }
};

/// The nearest folder of `output` that exists (the run makes the missing ones), through links:
/// the filesystem the archive will be written on.
std::filesystem::path existing_folder(const std::string& output) {
    std::error_code ec;
    std::filesystem::path folder = std::filesystem::weakly_canonical(std::filesystem::absolute(output), ec);
    if (ec) folder = std::filesystem::absolute(output);
    for (folder = folder.parent_path(); !folder.empty(); folder = folder.parent_path()) {
        if (std::filesystem::is_directory(folder, ec)) return folder;
        if (folder == folder.root_path()) break;
    }
    return {};
}

/// Creates `path` (O_EXCL: a name no one else holds) and writes `bytes` to it through to the
/// disk: a folder that refuses that (a quota, an I/O error) is not probed. A creation refused
/// halfway by HDF5 would end the process with status 1 when MPI finalises (hdf5.cpp,
/// file_close_failed), and a dry run must not fail for a probe.
bool room_for(const std::string& path, std::size_t bytes) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) return false;
    const std::vector<char> block(1 << 16, 0);
    bool ok = true;
    for (std::size_t done = 0; ok && done < bytes; done += block.size())
        ok = ::write(fd, block.data(), block.size()) == static_cast<ssize_t>(block.size());
    ok = ok && ::fdatasync(fd) == 0;
    return ::close(fd) == 0 && ok;
}
}  // namespace

std::optional<double> archive_seconds_per_replica(const CampaignSpec& spec, const std::string& output) {
    int mpi_on = 0;
    MPI_Initialized(&mpi_on);
    if (!mpi_on || spec.replicas.empty() || output.empty()) return std::nullopt;
    const std::filesystem::path beside = existing_folder(output);
    if (beside.empty()) return std::nullopt;
    char host[256] = "host";
    gethostname(host, sizeof host - 1);
    const ScratchFiles scratch{(beside / (".jamsim-write-probe." + std::string(host) + "." + std::to_string(getpid()) +
                                          "." + std::to_string(std::random_device{}() & 0xffffffu) + ".h5"))
                                   .string()};
    CampaignSpec probe = spec;
    probe.replicas = smallest_replicas(spec, 8);
    probe.predecessor.clear();
    probe.output = scratch.path;
    // Room for it many times over, and a write of four times its size through to the disk.
    const double bytes = archive_layout(probe).bytes + 1e6;
    std::error_code ec;
    const std::filesystem::space_info room = std::filesystem::space(beside, ec);
    if (ec || static_cast<double>(room.available) < 16 * bytes + 16e6) return std::nullopt;
    if (!room_for(scratch.path, static_cast<std::size_t>(4 * bytes))) return std::nullopt;
    std::filesystem::remove(scratch.path, ec);  // made afresh below (a truncation is dearer, and not timed)
    std::optional<Archive> archive;
    try {
        archive.emplace(Archive::create(MPI_COMM_SELF, scratch.path, probe));
        std::vector<double> seconds;
        for (std::size_t r = 0; r < probe.replicas.size(); ++r) {
            // No rows: whole rows of NaN are written, as for a short replica.
            const ReplicaResult result{.series = {}, .final_state = initial_system(probe.replicas[r])};
            const auto t0 = std::chrono::steady_clock::now();
            archive->mark_running(static_cast<std::int64_t>(r), 0, false);
            archive->write_done(static_cast<std::int64_t>(r), result, 0, 1.0);
            seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        archive->close();
        // The median: one fdatasync that meets the disk's other work would set the mean.
        std::sort(seconds.begin(), seconds.end());
        const std::size_t k = seconds.size();
        return k % 2 ? seconds[k / 2] : 0.5 * (seconds[k / 2 - 1] + seconds[k / 2]);
    } catch (const std::exception&) {
        // Closed here, not abandoned by an unwinding destructor (one process: no rank waits).
        try {
            if (archive) archive->close();
        } catch (const std::exception&) {}
        return std::nullopt;  // the run itself will say what the folder refuses
    }
}

}  // namespace jamsim
