#include "jamsim/archive/archive.hpp"

#include "archive_detail.hpp"

#include <algorithm>
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
#include "jamsim/observe/velocity_correlation.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

using archive_detail::kReasonLength;
using archive_detail::write_block;
using h5::check;
using h5::Handle;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A numeric per-replica column: a used parameter, or a derived figure.
struct Column {
    std::string name, units, description;
    std::function<double(const ReplicaParams&)> value;
};

/// The parameter columns of a campaign: every numeric parameter that its model uses for at
/// least one replica (NaN for replicas that do not use it), then the derived figures.
std::vector<Column> parameter_columns(const CampaignSpec& spec) {
    std::vector<Column> out;
    for (const auto& info : parameters()) {
        if (!is_numeric(info)) continue;
        if (std::none_of(spec.replicas.begin(), spec.replicas.end(),
                         [&](const ReplicaParams& p) { return uses_parameter(p, info.key); }))
            continue;
        out.push_back(
            {std::string(info.key), std::string(info.units), std::string(info.description),
             [&info](const ReplicaParams& p) { return uses_parameter(p, info.key) ? numeric_value(p, info) : kNaN; }});
    }
    out.push_back({"n_samples", "1", "rows of this replica in /timeseries",
                   [](const ReplicaParams& p) { return double(sample_count(p)); }});
    out.push_back({"estimated_cost", "particle force evaluations", "estimated N x steps x evaluations per step",
                   [](const ReplicaParams& p) { return estimated_cost(p); }});
    return out;
}

}  // namespace

ArchiveLayout archive_layout(const CampaignSpec& spec) {
    ArchiveLayout out;
    std::int64_t particles = 0;
    for (const auto& p : spec.replicas) {
        out.particle_offset.push_back(particles);
        particles += p.n;
        out.samples = std::max<hsize_t>(out.samples, static_cast<hsize_t>(sample_count(p)));
        out.bins = std::max<hsize_t>(out.bins, VelocityCorrelation::bins_for(box_side_for(p.n, p.phi, p.size_ratio)));
        out.frames = std::max<hsize_t>(out.frames, static_cast<hsize_t>(frame_count(p)));
    }
    out.particles = std::max<hsize_t>(1, static_cast<hsize_t>(particles));
    for (const auto& p : spec.replicas) {
        out.bytes += out.replica_bytes(p.n);
        out.frame_bytes += 8.0 * static_cast<double>(out.frames) * (2.0 * static_cast<double>(p.n) + 2.0);
    }
    return out;
}

double ArchiveLayout::configuration_bytes(std::int64_t n) const {
    const auto disks = static_cast<double>(n);
    return 8.0 * (3.0 * disks + static_cast<double>(frames) * (2.0 * disks + 2.0));
}

double ArchiveLayout::replica_bytes(std::int64_t n) const {
    const double rows = 8.0 * (static_cast<double>(samples) * static_cast<double>(std::size(kSampleColumns)) +
                               2.0 * static_cast<double>(bins));
    return rows + 8.0 * 40 + 256 + configuration_bytes(n);
}

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

Archive Archive::create(MPI_Comm comm, const std::string& path, const CampaignSpec& spec) {
    h5::quiet_errors();
    const auto fapl = h5::mpio_file_access(comm);
    Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                "create archive '" + path + "'");
    const hid_t f = file.get();
    const auto replicas = static_cast<hsize_t>(spec.replicas.size());
    const ArchiveLayout layout = archive_layout(spec);
    std::string created = utc_now();
    mpi::broadcast(created, 0, comm);  // attributes must be identical on every rank
    h5::write_attribute(f, "campaign", spec.name);
    h5::write_attribute(f, "spec_path", spec.path);
    h5::write_attribute(f, "spec_text", spec.text);
    h5::write_attribute(f, "spec_fingerprint", fingerprint(spec));
    // Text parameters are campaign-wide (they cannot be swept): root attributes.
    for (const ParamInfo* info : used_parameters(spec.replicas.front()))
        if (!is_numeric(*info))
            h5::write_attribute(f, std::string(info->key), show_value(get_value(spec.replicas.front(), *info)));
    {
        std::string warnings;  // advisory limits of the campaign, one per line ("" when none)
        for (const std::string& line : campaign_warnings(spec)) warnings.append(line).append("\n");
        h5::write_attribute(f, "warnings", warnings);
    }
    h5::write_attribute(f, "code_version", std::string(kVersion));
    h5::write_attribute(f, "build_flags", std::string(kBuildFlags));
    h5::write_attribute(f, "created", created);
    h5::write_attribute(f, "layout_version", std::int64_t{kArchiveLayoutVersion});
    h5::write_attribute(f, "n_replicas", static_cast<std::int64_t>(replicas));
    for (const char* g : {"replicas", "timeseries", "final"}) h5::create_group(f, g).close(g);

    const double nan = kNaN;
    const std::int8_t pending = 0;
    const std::int32_t no_rank = -1;
    const std::int64_t zero = 0;
    const std::vector<Column> columns = parameter_columns(spec);
    for (const auto& c : columns)
        h5::create_filled_dataset(f, "/replicas/" + c.name, H5T_NATIVE_DOUBLE, {replicas}, &nan, c.units,
                                  c.description);
    if (!spec.predecessor.empty()) {
        const std::int64_t none = -1;
        h5::create_filled_dataset(f, "/replicas/predecessor", H5T_NATIVE_INT64, {replicas}, &none, "1",
                                  "rate ladder: the replica whose end state starts this one (-1: none)");
    }
    {
        const std::uint64_t none = 0;
        h5::create_filled_dataset(f, "/replicas/identity", H5T_NATIVE_UINT64, {replicas}, &none, "1",
                                  "64-bit hash of the replica's model and physical parameters: with "
                                  "the seed, the key of its random numbers (the same replica in "
                                  "any campaign has the same identity)");
    }
    create_initial_columns(f, spec);
    h5::create_filled_dataset(f, "/replicas/status", H5T_NATIVE_INT8, {replicas}, &pending, "1",
                              "0 pending, 1 running, 2 done, 3 failed; written after the replica's data");
    h5::create_filled_dataset(f, "/replicas/rank", H5T_NATIVE_INT32, {replicas}, &no_rank, "1",
                              "MPI rank that ran the replica (-1: not run)");
    h5::create_filled_dataset(f, "/replicas/wall_seconds", H5T_NATIVE_DOUBLE, {replicas}, &nan, "s",
                              "wall time of the replica");
    h5::create_filled_dataset(f, "/replicas/rows_written", H5T_NATIVE_INT64, {replicas}, &zero, "1",
                              "rows of /timeseries written so far (partial while status is 1)");
    {
        const double none = 0.0;
        h5::create_filled_dataset(f, "/replicas/progress", H5T_NATIVE_DOUBLE, {replicas}, &none, "1",
                                  "fraction of the replica's steps done at its last checkpoint (1 when done)");
    }
    h5::create_filled_dataset(f, "/replicas/force_evaluations", H5T_NATIVE_INT64, {replicas}, &zero, "1",
                              "force evaluations of the replica");
    {
        const Handle rt = h5::fixed_string_type(kReasonLength);
        const char empty[kReasonLength] = {};
        h5::create_filled_dataset(f, "/replicas/failure_reason", rt.get(), {replicas}, empty, "",
                                  "why a failed replica failed (empty otherwise)");
    }
    // The bulk: allocated but never filled, so creating it writes nothing (a replica's rows
    // are defined once its status is done; its writer pads them with NaN to the row length).
    for (const auto& c : kSampleColumns)
        h5::create_unfilled_dataset(
            f, std::string("/timeseries/") + c.name, H5T_NATIVE_DOUBLE, {replicas, layout.samples}, c.units,
            std::string(c.description) + "; row = replica, NaN past n_samples (undefined unless status is done, "
                                         "past rows_written while running)");
    // Final configurations of all replicas end to end: replica r's N disks start at
    // /replicas/particle_offset[r] (no padding to the largest N).
    for (const char* name : {"x", "y", "diameter"})
        h5::create_unfilled_dataset(f, std::string("/final/") + name, H5T_NATIVE_DOUBLE, {layout.particles}, "d_s",
                                    std::string(name) +
                                        " of the final configurations, replica r at [particle_offset[r], "
                                        "particle_offset[r] + N[r]); x, y sheared coordinates in [0, L), "
                                        "lab x = x + box_strain y");
    h5::create_group(f, "correlation").close("correlation");
    h5::create_unfilled_dataset(
        f, "/correlation/x", H5T_NATIVE_DOUBLE, {replicas, layout.bins}, "d_s",
        "bin centres of g_y: lab x distance of disks within a strip |dy| < 1/2 (NaN past the replica's bins)");
    h5::create_unfilled_dataset(f, "/correlation/g_y", H5T_NATIVE_DOUBLE, {replicas, layout.bins}, "1",
                                "g_y(x) = <u_y(r) u_y(r + x)>/<u_y^2> over the steady state (thesis eq. 4.23)");
    h5::create_filled_dataset(f, "/replicas/particle_offset", H5T_NATIVE_INT64, {replicas}, &zero, "1",
                              "index of the replica's first disk in /final/x, /final/y, /final/diameter");
    h5::create_filled_dataset(f, "/final/box_side", H5T_NATIVE_DOUBLE, {replicas}, &nan, "d_s", "cell side L");
    h5::create_filled_dataset(f, "/final/box_strain", H5T_NATIVE_DOUBLE, {replicas}, &nan, "1",
                              "Lees-Edwards strain gamma in [-1/2, 1/2)");
    if (layout.frames > 0) {  // only with [run] frame_interval: archives without it are unchanged
        h5::create_group(f, "frames").close("frames");
        for (const char* name : {"x", "y"})
            h5::create_unfilled_dataset(
                f, std::string("/frames/") + name, H5T_NATIVE_DOUBLE, {layout.frames, layout.particles}, "d_s",
                std::string(name) + " of configuration frame k (row k) of every replica, "
                                    "replica r at columns [particle_offset[r], particle_offset[r] + N[r]) in tag "
                                    "order; sheared coordinates in [0, L), lab x = x + box_strain y; defined where "
                                    "/frames/strain is not NaN");
        h5::create_filled_dataset(f, "/frames/strain", H5T_NATIVE_DOUBLE, {replicas, layout.frames}, &nan, "1",
                                  "strain (time at rate 0, tau) of frame k of replica r (NaN: no frame)");
        h5::create_filled_dataset(f, "/frames/box_strain", H5T_NATIVE_DOUBLE, {replicas, layout.frames}, &nan, "1",
                                  "Lees-Edwards strain gamma in [-1/2, 1/2) of frame k of replica r");
    }

    // Parameter columns: rank 0 writes them (independently), then everyone flushes.
    if (mpi::rank(comm) == 0) {
        for (const auto& c : columns) {
            std::vector<double> v;
            for (const auto& p : spec.replicas) v.push_back(c.value(p));
            write_block(f, "/replicas/" + c.name, H5T_NATIVE_DOUBLE, {0}, {replicas}, v.data());
        }
        if (!spec.predecessor.empty())
            write_block(f, "/replicas/predecessor", H5T_NATIVE_INT64, {0}, {replicas}, spec.predecessor.data());
        std::vector<std::uint64_t> ids;
        for (const auto& p : spec.replicas) ids.push_back(replica_identity(p));
        write_block(f, "/replicas/identity", H5T_NATIVE_UINT64, {0}, {replicas}, ids.data());
        write_block(f, "/replicas/particle_offset", H5T_NATIVE_INT64, {0}, {replicas}, layout.particle_offset.data());
    }
    check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush '" + path + "'");
    return Archive(std::move(file), comm, layout);
}

Archive Archive::open(MPI_Comm comm, const std::string& path) {
    h5::quiet_errors();
    const auto fapl = h5::mpio_file_access(comm);
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose, "open archive '" + path + "'");
    ArchiveLayout layout;
    const Handle dxpl = h5::independent_transfer();
    layout.particle_offset =
        h5::read_all<std::int64_t>(file.get(), "/replicas/particle_offset", H5T_NATIVE_INT64, dxpl.get());
    layout.samples = h5::dataset_shape(file.get(), "/timeseries/time").at(1);
    layout.bins = h5::dataset_shape(file.get(), "/correlation/g_y").at(1);
    layout.particles = h5::dataset_shape(file.get(), "/final/x").at(0);
    if (h5::exists(file.get(), "/frames/strain")) layout.frames = h5::dataset_shape(file.get(), "/frames/strain").at(1);
    return Archive(std::move(file), comm, std::move(layout));
}

std::string Archive::check_existing(const std::string& path, const CampaignSpec& spec) {
    h5::quiet_errors();
    if (H5Fis_hdf5(path.c_str()) <= 0) return "'" + path + "' exists but is not an HDF5 file";
    try {
        const Handle file = h5::open_unlocked_readonly(path);
        const std::string stored = h5::read_string_attribute(file.get(), "spec_fingerprint");
        if (stored.empty()) return "'" + path + "' is not a jamsim campaign archive";
        const std::string wanted = fingerprint(spec);
        if (stored == wanted) return "";
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
            return "'" + path + "' was written by another version of jamsim (" + version_a + "; this one writes " +
                   version_b + "): start a new archive";
        while (la == lb && std::getline(a, la) && std::getline(b, lb)) {}
        return "'" + path + "' belongs to a different campaign (archive: \"" + la + "\", this spec: \"" + lb + "\")";
    } catch (const h5::Error& e) { return "'" + path + "' cannot be read as a campaign archive: " + e.what(); }
}

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
    const auto r = static_cast<hsize_t>(replica);
    const std::int32_t who = rank;
    write_block(file_.get(), "/replicas/rank", H5T_NATIVE_INT32, {r}, {1}, &who);
    // Its rows NaN until written (the datasets are not filled): partial rows of a running
    // replica end in NaN, as finished rows do past n_samples.
    if (!keep_rows) { clear_rows(replica); }
    const auto s = static_cast<std::int8_t>(ReplicaStatus::Running);
    write_block(file_.get(), "/replicas/status", H5T_NATIVE_INT8, {r}, {1}, &s);
    // A replica run again (--retry-failed) forgets an old failure; after the status, so that
    // an interruption in between never leaves a failed replica without its reason.
    const char no_reason[kReasonLength] = {};
    const Handle rt = h5::fixed_string_type(kReasonLength);
    write_block(file_.get(), "/replicas/failure_reason", rt.get(), {r}, {1}, no_reason);
}

void Archive::write_done(std::int64_t replica, const ReplicaResult& result, int rank) {
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
    // Last: the flag that makes the rows above valid.
    const auto s = static_cast<std::int8_t>(ReplicaStatus::Done);
    write_block(f, "/replicas/status", H5T_NATIVE_INT8, {r}, {1}, &s);
}

void Archive::write_progress(std::int64_t replica, const TimeSeries& series, std::size_t from_row, double progress) {
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
    const hid_t f = file_.get();
    const auto r = static_cast<hsize_t>(replica);
    // Its rows: NaN (the datasets are not filled, and a reader may ignore the status).
    clear_rows(replica);
    char text[kReasonLength] = {};
    reason.copy(text, kReasonLength - 1);
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
    for (const char* p : {"/replicas/initial_state", "/replicas/initial_source"})  // where both have them
        if (H5Lexists(src.get(), p, H5P_DEFAULT) > 0 && H5Lexists(file_.get(), p, H5P_DEFAULT) > 0)
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

void Archive::stamp(const std::string& attribute) {
    std::string now = utc_now();
    mpi::broadcast(now, 0, comm_);
    // Metadata changes are collective, and HDF5 needs every rank's metadata cache to take
    // the same path through them. The independent writes of a run (each rank opens the
    // datasets of its own replicas) leave the caches different, which deadlocked this very
    // attribute write with 64 ranks and 10^4 replicas; closing and reopening the file makes
    // them the same (empty) first.
    {
        const ssize_t length = H5Fget_name(file_.get(), nullptr, 0);
        check(static_cast<herr_t>(length < 0 ? -1 : 0), "name of the archive");
        std::string path(static_cast<std::size_t>(length) + 1, '\0');
        check(static_cast<herr_t>(H5Fget_name(file_.get(), path.data(), path.size()) < 0 ? -1 : 0),
              "name of the archive");
        path.resize(static_cast<std::size_t>(length));
        file_.close("archive '" + path + "'");
        const auto fapl = h5::mpio_file_access(comm_);
        file_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose, "reopen archive '" + path + "'");
    }
    const hid_t f = file_.get();
    h5::replace_attribute(f, attribute, now);
    h5::replace_attribute(f, "n_ranks", static_cast<std::int64_t>(mpi::size(comm_)));
    check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush archive");
}

void Archive::close() { file_.close("archive"); }

Archive::~Archive() {
    if (std::uncaught_exceptions() > 0) file_.abandon();
}

}  // namespace jamsim
