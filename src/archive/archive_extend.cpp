// Extending a campaign archive to longer runs (Archive::check_extension, Archive::extend).
#include <filesystem>
#include <sstream>

#include "jamsim/archive/archive.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/run/model_registry.hpp"
#include "archive_detail.hpp"

namespace jamsim {

using archive_detail::write_block;
using h5::Handle;

namespace {
/// "0 model=RD0 N=64 ... strain=0.4 ..." without its strain= and time= fields, and those values.
std::pair<std::string, std::vector<double>> split_run_length(const std::string& line) {
    std::istringstream in(line);
    std::string token, rest;
    std::vector<double> lengths;
    while (in >> token) {
        if (token.rfind("strain=", 0) == 0 || token.rfind("time=", 0) == 0) {
            lengths.push_back(std::strtod(token.c_str() + token.find('=') + 1, nullptr));
            continue;
        }
        rest += token + ' ';
    }
    return {rest, lengths};
}
}  // namespace

std::string Archive::check_extension(const std::string& path, const CampaignSpec& spec) {
    h5::quiet_errors();
    std::string stored;
    try {
        stored = h5::read_string_attribute(h5::open_unlocked_readonly(path).get(), "spec_fingerprint");
    } catch (const h5::Error& e) { return e.what(); }
    std::istringstream a(stored), b(fingerprint(spec));
    std::string la, lb;
    bool longer = false;
    for (std::size_t k = 0;; ++k) {
        const bool got_a = static_cast<bool>(std::getline(a, la));
        const bool got_b = static_cast<bool>(std::getline(b, lb));
        if (!got_a && !got_b) break;
        if (got_a != got_b) return "the number of replicas differs";
        if (k == 0) {
            if (la != lb) return "another campaign name, replica count or version";
            continue;
        }
        if (k - 1 < spec.replicas.size() && !model_of(spec.replicas[k - 1]).extendable && la != lb)
            return "replica " + std::to_string(k - 1) + " differs, and " + spec.replicas[k - 1].model +
                   " cannot be extended (its strain is not a run length)";
        const auto [ra, va] = split_run_length(la);
        const auto [rb, vb] = split_run_length(lb);
        if (ra != rb || va.size() != vb.size())
            return "replica " + std::to_string(k - 1) + " differs in more than its run length";
        for (std::size_t j = 0; j < va.size(); ++j) {
            if (vb[j] < va[j]) return "replica " + std::to_string(k - 1) + " would run shorter";
            longer = longer || vb[j] > va[j];
        }
    }
    return longer ? "" : "no replica runs longer";
}

std::string Archive::remove_interrupted_extension(const std::string& path) {
    namespace fs = std::filesystem;
    const std::string next = path + ".extending";
    std::error_code ec;
    // Only beside the archive it would have replaced: without it, the file may be the only copy
    // (the archive moved away). A dangling link counts as a file left behind.
    const auto is_left = [&](const std::string& p) {
        return fs::symlink_status(p, ec).type() != fs::file_type::not_found;
    };
    if (!fs::is_regular_file(path, ec) || (!is_left(next) && !is_left(creation_marker(next)))) return "";
    for (const std::string& left : {next, creation_marker(next)}) {
        std::filesystem::remove(left, ec);
        if (ec) throw h5::Error("cannot remove '" + left + "': " + ec.message());
    }
    return "removed '" + next + "', left by an extension that a kill interrupted before it replaced '" + path +
           "' (which is whole)";
}

void Archive::extend(MPI_Comm comm, const std::string& path, const CampaignSpec& spec) {
    const std::string next = path + ".extending";
    std::vector<ReplicaStatus> before;
    if (mpi::rank(comm) == 0) before = read_stored_campaign(path).status;
    Archive out = create(comm, next, spec);
    // A rate ladder's later replicas started from their predecessor's end state at the old
    // run length; the longer campaign starts them from the end state at the new one, so they
    // run again from there (pending, their rows and final checkpoints dropped), as a campaign
    // run in one go would have run them.
    std::vector<std::size_t> rerun;
    if (mpi::rank(comm) == 0)
        for (std::size_t r = 0; r < before.size(); ++r) {
            if (!spec.predecessor.empty() && spec.predecessor[r] >= 0) {
                rerun.push_back(r);
                continue;
            }
            // A replica that was running (a stopped or killed run) keeps its rows and frames
            // too: it goes on from its checkpoint, which counts on the rows and frames before it
            // being in the archive (dropped, its early frames were never written again).
            if (before[r] == ReplicaStatus::Pending) continue;
            out.import_replica(path, static_cast<std::int64_t>(r));
            if (before[r] == ReplicaStatus::Failed) continue;
            // Its rows so far stay visible, as partial rows of a replica still running.
            const auto id = static_cast<hsize_t>(r);
            const ReplicaParams& p = spec.replicas[r];
            const auto s = static_cast<std::int8_t>(ReplicaStatus::Running);
            double progress = 0;
            {
                const Handle src = h5::open_unlocked_readonly(path);
                std::int64_t rows = 0;
                h5::read_block(src.get(), "/replicas/rows_written", H5T_NATIVE_INT64, {id}, {1}, &rows);
                progress =
                    static_cast<double>(rows - 1) / static_cast<double>(std::max<std::int64_t>(sample_count(p) - 1, 1));
            }
            write_block(out.file_.get(), "/replicas/progress", H5T_NATIVE_DOUBLE, {id}, {1}, &progress);
            write_block(out.file_.get(), "/replicas/status", H5T_NATIVE_INT8, {id}, {1}, &s);
        }
    // Their final checkpoints go before the rename: the old archive never needs them (an
    // extension reruns them anyway), the new one must not continue from them.
    for (const std::size_t r : rerun) {
        std::error_code ignored;
        std::filesystem::remove(checkpoint_path(path, static_cast<std::int64_t>(r)), ignored);
        std::filesystem::remove(checkpoint_path(path, static_cast<std::int64_t>(r)) + ".tmp", ignored);
        std::filesystem::remove(rebuild_state_path(path, static_cast<std::int64_t>(r)), ignored);
    }
    out.stamp("extended");
    out.close();
    if (mpi::rank(comm) == 0) {
        std::error_code ec;
        std::filesystem::rename(next, path, ec);
        if (ec) throw h5::Error("cannot rename '" + next + "' to '" + path + "': " + ec.message());
    }
    mpi::check(MPI_Barrier(comm), "MPI_Barrier");
}

}  // namespace jamsim
