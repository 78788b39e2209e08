// Reading an archive serially: its stored campaign and the summary of `jamsim status`.
#include "jamsim/archive/archive.hpp"
#include "archive_detail.hpp"
#include "jamsim/io/checkpoint_file.hpp"

#include <limits>

namespace jamsim {

using archive_detail::kReasonLength;
using h5::check;
using h5::Handle;

StoredCampaign read_stored_campaign(const std::string& path) {
    h5::quiet_errors();
    const Handle file = h5::open_unlocked_readonly(path);
    const std::string text = h5::read_string_attribute(file.get(), "spec_text");
    if (text.empty()) throw h5::Error("'" + path + "' is not a jamsim campaign archive");
    StoredCampaign out;
    try {
        out.spec = archive_detail::parse_stored_campaign(text, h5::read_string_attribute(file.get(), "spec_path"));
    } catch (const SpecError& e) {  // the archive's copy is damaged, not the campaign file
        throw SpecError("'" + path + "' is damaged: " + e.what() +
                        "; jamsim writes no such archive (a hand-edited or broken copy?)");
    }
    for (auto v : h5::read_all<std::int8_t>(file.get(), "/replicas/status", H5T_NATIVE_INT8))
        out.status.push_back(static_cast<ReplicaStatus>(v));
    return out;
}

ArchiveSummary summarize_archive(const std::string& path) {
    h5::quiet_errors();
    const Handle file = h5::open_unlocked_readonly(path);
    ArchiveSummary s;
    s.campaign = h5::read_string_attribute(file.get(), "campaign");
    if (s.campaign.empty()) throw h5::Error("'" + path + "' is not a jamsim campaign archive");
    s.started = h5::read_string_attribute(file.get(), "run_started");
    s.finished = h5::read_string_attribute(file.get(), "run_finished");
    s.merged = h5::read_string_attribute(file.get(), "merged");
    const auto status = h5::read_all<std::int8_t>(file.get(), "/replicas/status", H5T_NATIVE_INT8);
    const auto wall = h5::read_all<double>(file.get(), "/replicas/wall_seconds", H5T_NATIVE_DOUBLE);
    const auto cost = h5::read_all<double>(file.get(), "/replicas/estimated_cost", H5T_NATIVE_DOUBLE);
    const auto progress = h5::read_all<double>(file.get(), "/replicas/progress", H5T_NATIVE_DOUBLE);
    if (H5Aexists(file.get(), "n_ranks") > 0) s.ranks = h5::read_int64_attribute(file.get(), "n_ranks");
    const Handle rt = h5::fixed_string_type(kReasonLength);
    std::vector<char> reasons(status.size() * kReasonLength);
    {
        Handle set(H5Dopen2(file.get(), "/replicas/failure_reason", H5P_DEFAULT), H5Dclose, "open failure_reason");
        if (!status.empty())
            check(H5Dread(set.get(), rt.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, reasons.data()), "read failure_reason");
    }
    s.wall_seconds = wall;
    s.progress = progress;
    for (std::size_t r = 0; r < status.size(); ++r) {
        switch (static_cast<ReplicaStatus>(status[r])) {
        case ReplicaStatus::Pending:
            ++s.pending;
            s.cost_left += cost[r];
            break;
        case ReplicaStatus::Running:
            ++s.running;
            s.cost_left += cost[r] * (1.0 - progress[r]);
            s.in_progress.push_back({static_cast<std::int64_t>(r), progress[r]});
            if (const auto note = read_progress_note(progress_note_path(path, static_cast<std::int64_t>(r)))) {
                s.in_progress.back().noted = note->fraction;
                s.in_progress.back().note_age = note->age_seconds;
            }
            break;
        case ReplicaStatus::Done:
            ++s.done;
            s.wall_seconds_done += wall[r];
            s.cost_done += cost[r];
            break;
        case ReplicaStatus::Failed:
            ++s.failed;
            s.failures.push_back("replica " + std::to_string(r) + ": " + std::string(&reasons[r * kReasonLength]));
            break;
        }
    }
    return s;
}

}  // namespace jamsim
