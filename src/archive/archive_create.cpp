// Creating a campaign archive (archive.hpp, Archive::create): its layout, its attributes and
// every dataset, filled with "not run yet" where a reader may look before a replica is done.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "archive_detail.hpp"
#include "jamsim/archive/archive.hpp"
#include "jamsim/core/version.hpp"
#include "jamsim/io/read_deadline.hpp"
#include "jamsim/observe/velocity_correlation.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

using archive_detail::Column;
using archive_detail::kReasonLength;
using archive_detail::kStampAttributes;
using archive_detail::kStampBytes;
using archive_detail::parameter_columns;
using archive_detail::write_block;
using h5::Handle;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

namespace archive_detail {

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

}  // namespace archive_detail

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

namespace {

/// The root attributes: the campaign, its text and fingerprint, its text parameters and
/// warnings, the code's version and the layout's (`created` identical on every rank).
void write_root_attributes(hid_t f, const CampaignSpec& spec, const std::string& created, hsize_t replicas) {
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
    // The stamps of later runs, merges, extensions and growths, made now (empty) with room
    // for a time stamp: they are written over where they stand (Archive::stamp), so that
    // a stamp whose write fails on one rank cannot leave the file shorter than its superblock.
    for (const char* stamp : kStampAttributes) h5::create_fixed_text_attribute(f, stamp, kStampBytes);
    h5::write_attribute(f, "n_ranks", std::int64_t{0});
}

/// /replicas: the parameter columns, identity, the initial-state columns and the status
/// columns a run fills in.
void create_replica_columns(hid_t f, const CampaignSpec& spec, const std::vector<Column>& columns, hsize_t replicas) {
    const double nan = kNaN;
    const std::int8_t pending = 0;
    const std::int32_t no_rank = -1;
    const std::int64_t zero = 0;
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
    {
        const double none = 0.0;
        h5::create_filled_dataset(f, "/replicas/threads", H5T_NATIVE_DOUBLE, {replicas}, &none, "1",
                                  "mean OpenMP threads of the replica's kernel over the run that finished it, "
                                  "weighted by time (cores lent by idle ranks come and go at samples; 0: not done, "
                                  "or not recorded); its data do not depend on them");
    }
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
}

/// The bulk (time series, final configurations, g_y), allocated but never filled.
void create_bulk(hid_t f, const ArchiveLayout& layout, hsize_t replicas) {
    const double nan = kNaN;
    const std::int64_t zero = 0;
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
}

/// Configuration frames, only with [run] frame_interval (archives without it are unchanged).
void create_frames(hid_t f, const ArchiveLayout& layout, hsize_t replicas) {
    const double nan = kNaN;
    if (layout.frames == 0) return;
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

/// The parameter columns' values, written by rank 0 alone (independent writes).
void write_parameter_columns(hid_t f, const CampaignSpec& spec, const std::vector<Column>& columns,
                             const ArchiveLayout& layout, hsize_t replicas) {
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

}  // namespace

Archive Archive::create(MPI_Comm comm, const std::string& path, const CampaignSpec& spec) {
    h5::quiet_errors();
    // The marker, not a temporary name renamed into place: MPI-IO takes no longer names.
    const std::string marker = creation_marker(path);
    const bool root = mpi::rank(comm) == 0;
    int failed = 0;
    if (root) {
        std::ofstream note(marker, std::ios::trunc);
        note << "jamsim: the archive beside this file is being created; a kill left it half-made if this "
                "file is still here\n";
        note.flush();
        failed = note ? 0 : 1;
    }
    mpi::check(MPI_Bcast(&failed, 1, MPI_INT, 0, comm), "MPI_Bcast");
    if (failed) throw h5::Error("cannot write '" + marker + "'");
    // Collective writes from here to the barrier: a write that fails on one rank leaves the
    // ranks waiting for each other inside HDF5 (read_deadline.hpp). The datasets are filled as
    // they are made, so the limit grows with the archive (20 MB/s).
    const ArchiveLayout layout = archive_layout(spec);
    const WriteDeadline deadline(path, "its creation", mpi::rank(comm),
                                 write_deadline_seconds() + static_cast<double>(layout.bytes) / 20e6);
    Handle file;
    try {
        file = h5::create_parallel(comm, path);
    } catch (const h5::OpenRefused&) {
        std::error_code ignored;
        if (root) std::filesystem::remove(marker, ignored);  // nothing was made
        throw;
    }
    const hid_t f = file.get();
    const auto replicas = static_cast<hsize_t>(spec.replicas.size());
    std::string created = utc_now();
    mpi::broadcast(created, 0, comm);  // attributes must be identical on every rank
    write_root_attributes(f, spec, created, replicas);
    for (const char* g : {"replicas", "timeseries", "final"}) h5::create_group(f, g).close(g);
    const std::vector<Column> columns = parameter_columns(spec);
    create_replica_columns(f, spec, columns, replicas);
    create_bulk(f, layout, replicas);
    create_frames(f, layout, replicas);
    if (mpi::rank(comm) == 0) write_parameter_columns(f, spec, columns, layout, replicas);
    h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush '" + path + "'");
    mpi::check(MPI_Barrier(comm), "MPI_Barrier");  // every rank's part is written
    if (root) {
        std::error_code ec;
        std::filesystem::remove(marker, ec);
        if (ec) throw h5::Error("cannot remove '" + marker + "': " + ec.message());
    }
    return Archive(std::move(file), comm, layout);
}

std::string Archive::undo_interrupted_creation(const std::string& path) {
    const std::string marker = creation_marker(path);
    std::error_code ec;
    if (!std::filesystem::exists(marker, ec)) return "";
    const bool had_file = std::filesystem::exists(path, ec);
    std::filesystem::remove(path, ec);
    if (ec) throw h5::Error("cannot remove '" + path + "': " + ec.message());
    std::filesystem::remove(marker, ec);
    if (ec) throw h5::Error("cannot remove '" + marker + "': " + ec.message());
    return had_file ? "removed '" + path + "', an archive whose creation was interrupted (nothing had run in it)"
                    : "removed '" + marker + "', left by an interrupted creation";
}

}  // namespace jamsim
