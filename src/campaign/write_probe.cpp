// The archive's writes per replica, measured beside the output (write_probe.hpp).
#include "jamsim/campaign/write_probe.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
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
}  // namespace

std::optional<double> archive_seconds_per_replica(const CampaignSpec& spec, const std::string& output) {
    int mpi_on = 0;
    MPI_Initialized(&mpi_on);
    if (!mpi_on || spec.replicas.empty() || output.empty()) return std::nullopt;
    const std::filesystem::path beside = std::filesystem::absolute(output).parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(beside, ec)) return std::nullopt;
    char host[256] = "host";
    gethostname(host, sizeof host - 1);
    const ScratchFiles scratch{
        (beside / (".jamsim-write-probe." + std::string(host) + "." + std::to_string(getpid()) + ".h5")).string()};
    CampaignSpec probe = spec;
    probe.replicas = smallest_replicas(spec, 8);
    probe.predecessor.clear();
    probe.output = scratch.path;
    // Room for it many times over: a creation that a full disk or quota refuses halfway ends
    // the process with status 1 when MPI finalises (hdf5.cpp, file_close_failed), and a dry
    // run must not fail for a probe.
    const std::filesystem::space_info room = std::filesystem::space(beside, ec);
    if (ec || static_cast<double>(room.available) < 16 * archive_layout(probe).bytes + 16e6) return std::nullopt;
    try {
        Archive archive = Archive::create(MPI_COMM_SELF, scratch.path, probe);
        double seconds = 0;
        for (std::size_t r = 0; r < probe.replicas.size(); ++r) {
            // No rows: whole rows of NaN are written, as for a short replica.
            const ReplicaResult result{.series = {}, .final_state = initial_system(probe.replicas[r])};
            const auto t0 = std::chrono::steady_clock::now();
            archive.mark_running(static_cast<std::int64_t>(r), 0, false);
            archive.write_done(static_cast<std::int64_t>(r), result, 0, 1.0);
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        archive.close();
        return seconds / static_cast<double>(probe.replicas.size());
    } catch (const std::exception&) {
        return std::nullopt;  // the run itself will say what the directory refuses
    }
}

}  // namespace jamsim
