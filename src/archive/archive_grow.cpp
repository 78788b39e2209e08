// Growing a campaign archive in place: more replicas in its sweep (Archive::check_growth,
// Archive::grow, Archive::finish_growth); the same replica in two archives compared
// (Archive::replica_difference, for jamsim merge).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string_view>

#include "jamsim/archive/archive.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

using h5::Handle;

namespace {

namespace fs = std::filesystem;

std::string growing_path(const std::string& path) { return path + ".growing"; }

/// The file that marks a growth's checkpoint folder as made by the growth: a folder of that
/// name without it (a user's, a copy's) never replaces the archive's checkpoints.
constexpr const char* kGrowthMarker = ".growth";

/// The replica id of a checkpoint file name (replica_<id>.h5 or end_<id>.h5) and the
/// prefix; id −1 for any other file (a .tmp left by a kill).
std::pair<std::string, long long> checkpoint_name(const std::string& name) {
    for (const char* prefix : {"replica_", "end_"}) {
        long long id = -1;
        char tail[8] = {};
        const std::string format = std::string(prefix) + "%lld.h%7s";
        if (name.rfind(prefix, 0) == 0 && std::sscanf(name.c_str(), format.c_str(), &id, tail) == 2 &&
            std::string_view(tail) == "5" && name == prefix + std::to_string(id) + ".h5")
            return {prefix, id};
    }
    return {"", -1};
}

}  // namespace

std::string Archive::check_growth(const std::string& path, const CampaignSpec& spec,
                                  std::vector<std::int64_t>& source) {
    StoredCampaign stored;
    try {
        stored = read_stored_campaign(path);
    } catch (const std::exception& e) { return e.what(); }
    const CampaignSpec& before = stored.spec;
    if (const std::string differs = settings_difference(before, spec, "archive", "file"); !differs.empty()) {
        // A longer run and more replicas at once: say which order works.
        const std::string_view run_length[] = {"[run] strain", "[run] time"};
        bool only_length = true;
        std::size_t start = 0;
        while (start < differs.size()) {
            const std::size_t end = std::min(differs.find("; ", start), differs.size());
            const std::string_view item(differs.data() + start, end - start);
            only_length = only_length && (item.rfind(run_length[0], 0) == 0 || item.rfind(run_length[1], 0) == 0);
            start = end + 2;
        }
        if (only_length && before.replicas.size() != spec.replicas.size())
            return "the campaign settings differ (" + differs +
                   ") and so does the sweep: a campaign is extended to a longer run or grown by "
                   "more replicas, not both at once (run the archive's sweep with the longer run "
                   "first, then the grown sweep)";
        return "the campaign settings differ: " + differs;
    }
    // The same replica: the same parameters and seed (its fingerprint line, without its id).
    std::map<std::string, std::vector<std::int64_t>> unmatched;  // description -> archive ids
    for (std::size_t r = before.replicas.size(); r-- > 0;)
        unmatched[describe(before.replicas[r])].push_back(static_cast<std::int64_t>(r));
    source.assign(spec.replicas.size(), -1);
    for (std::size_t k = 0; k < spec.replicas.size(); ++k) {
        auto it = unmatched.find(describe(spec.replicas[k]));
        if (it == unmatched.end() || it->second.empty()) continue;
        source[k] = it->second.back();  // in the archive's order, for replicas listed twice
        it->second.pop_back();
    }
    std::vector<char> kept(before.replicas.size(), 0);
    for (const std::int64_t from : source)
        if (from >= 0) kept[static_cast<std::size_t>(from)] = 1;
    for (std::size_t r = 0; r < kept.size(); ++r)
        if (!kept[r])
            return "replica " + std::to_string(r) + " of the archive (" + describe(before.replicas[r]) +
                   ") is not in the file's sweep: a campaign grows by more replicas, it keeps "
                   "every one it has" +
                   (spec.predecessor.empty() ? ""
                                             : " (in a rate ladder a new rate changes where the "
                                               "lower rates of its chain start)");
    for (std::size_t k = 0; k < spec.replicas.size(); ++k) {
        const std::int64_t before_id = spec.predecessor.empty() ? -1 : spec.predecessor[k];
        if (source[k] < 0 && before_id >= 0 && source[static_cast<std::size_t>(before_id)] >= 0)
            return "the new replica " + std::to_string(k) + " (" + describe(spec.replicas[k]) +
                   ") would continue a rate ladder from replica " +
                   std::to_string(source[static_cast<std::size_t>(before_id)]) +
                   " of the archive, whose end state is not kept: a rate ladder grows by whole "
                   "chains (more N, phi or seeds), not by a lower rate";
    }
    return "";
}

void Archive::grow(MPI_Comm comm, const std::string& path, const CampaignSpec& spec,
                   const std::vector<std::int64_t>& source) {
    const std::string next = growing_path(path);
    const bool root = mpi::rank(comm) == 0;
    std::vector<ReplicaStatus> before;
    if (root) {
        before = read_stored_campaign(path).status;
        // What a growth killed before its rename left (finish_growth removed it; once more).
        std::error_code ignored;
        fs::remove_all(checkpoint_folder(next), ignored);
    }
    Archive out = create(comm, next, spec);
    if (root)
        for (std::size_t k = 0; k < source.size(); ++k) {
            if (source[k] < 0) continue;
            if (before.at(static_cast<std::size_t>(source[k])) == ReplicaStatus::Pending) continue;
            out.import_replica(path, source[k], static_cast<std::int64_t>(k));
        }
    out.stamp("grown");
    out.close();
    if (root) {
        // The checkpoints follow their replicas: linked (copied where links are not
        // possible) into the new archive's folder under their new ids; the old folder stays
        // as it is until the new archive has replaced the old one.
        std::error_code ec;
        const fs::path old_folder = checkpoint_folder(path);
        if (fs::is_directory(old_folder, ec)) {
            std::map<std::int64_t, std::int64_t> new_id;
            for (std::size_t k = 0; k < source.size(); ++k)
                if (source[k] >= 0) new_id[source[k]] = static_cast<std::int64_t>(k);
            const fs::path folder = checkpoint_folder(next);
            fs::create_directories(folder, ec);
            if (ec) throw h5::Error("cannot create '" + folder.string() + "': " + ec.message());
            {
                std::ofstream marker(folder / kGrowthMarker);
                marker << "jamsim: the checkpoints of the archive growing from '" << path << "'\n";
                if (!marker.flush()) throw h5::Error("cannot write '" + (folder / kGrowthMarker).string() + "'");
            }
            for (const auto& entry : fs::directory_iterator(old_folder, ec)) {
                const auto [prefix, id] = checkpoint_name(entry.path().filename().string());
                const auto it = new_id.find(id);
                if (id < 0 || it == new_id.end()) continue;  // a .tmp of a kill: dropped
                const std::string target =
                    prefix == "end_" ? end_state_path(next, it->second) : checkpoint_path(next, it->second);
                fs::create_hard_link(entry.path(), target, ec);
                if (ec) fs::copy_file(entry.path(), target, fs::copy_options::overwrite_existing, ec);
                if (ec)
                    throw h5::Error("cannot copy the checkpoint '" + entry.path().string() + "' to '" + target +
                                    "': " + ec.message());
            }
            if (ec) throw h5::Error("cannot list '" + old_folder.string() + "': " + ec.message());
        }
        fs::rename(next, path, ec);  // the growth happens here
        if (ec) throw h5::Error("cannot rename '" + next + "' to '" + path + "': " + ec.message());
        finish_growth(path);
    }
    mpi::check(MPI_Barrier(comm), "MPI_Barrier");
}

std::string Archive::finish_growth(const std::string& path) {
    const std::string next = growing_path(path);
    const fs::path folder = checkpoint_folder(path), next_folder = checkpoint_folder(next);
    std::error_code ec;
    fs::remove(creation_marker(next), ec);  // killed while `next` was being made
    if (fs::exists(next, ec)) {             // killed before its rename: the old archive is whole
        fs::remove(next, ec);
        if (ec) throw h5::Error("cannot remove '" + next + "': " + ec.message());
        fs::remove_all(next_folder, ec);
        if (ec) throw h5::Error("cannot remove '" + next_folder.string() + "': " + ec.message());
        return "removed '" + next +
               "', left by a growth that was interrupted before it replaced "
               "the archive (the archive is as it was)";
    }
    if (!fs::exists(next_folder, ec)) return "";
    if (!fs::exists(next_folder / kGrowthMarker, ec))
        return "left '" + next_folder.string() +
               "' as it is: it is not a growth's checkpoint folder (no marker in it), and the checkpoints of '" + path +
               "' stay where they are";
    // Renamed: the archive is the grown one, and its checkpoints are those under the new ids.
    fs::remove_all(folder, ec);
    if (ec) throw h5::Error("cannot remove '" + folder.string() + "': " + ec.message());
    fs::rename(next_folder, folder, ec);
    if (ec)
        throw h5::Error("cannot rename '" + next_folder.string() + "' to '" + folder.string() + "': " + ec.message());
    fs::remove(folder / kGrowthMarker, ec);
    return "completed the growth of '" + path + "' (its checkpoints under the new replica ids)";
}

std::string Archive::replica_difference(const std::string& a, std::int64_t a_replica, const std::string& b,
                                        std::int64_t b_replica) {
    const Handle fa = h5::open_unlocked_readonly(a), fb = h5::open_unlocked_readonly(b);
    const auto ra = static_cast<hsize_t>(a_replica), rb = static_cast<hsize_t>(b_replica);
    // Bitwise, NaN equal to NaN (a row's padding).
    const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
        const std::size_t m = std::min(x.size(), y.size());
        for (std::size_t k = 0; k < std::max(x.size(), y.size()); ++k) {
            const double u = k < x.size() ? x[k] : std::nan(""), v = k < y.size() ? y[k] : std::nan("");
            if (std::isnan(u) && std::isnan(v)) continue;
            if (k >= m || std::memcmp(&u, &v, sizeof u) != 0) return false;
        }
        return true;
    };
    const auto row = [](hid_t f, const std::string& path, hsize_t r) {
        const std::vector<hsize_t> dims = h5::dataset_shape(f, path);
        const hsize_t length = dims.size() == 2 ? dims[1] : 1;
        std::vector<double> out(length);
        if (dims.size() == 2)
            h5::read_block(f, path, H5T_NATIVE_DOUBLE, {r, 0}, {1, length}, out.data());
        else
            h5::read_block(f, path, H5T_NATIVE_DOUBLE, {r}, {1}, out.data());
        return out;
    };
    std::vector<std::string> paths;
    for (const auto& c : kSampleColumns) paths.push_back(std::string("/timeseries/") + c.name);
    for (const char* p : {"/correlation/x", "/correlation/g_y", "/final/box_side", "/final/box_strain"})
        paths.emplace_back(p);
    for (const auto& path : paths)
        if (!same(row(fa.get(), path, ra), row(fb.get(), path, rb))) return path;
    const auto disks = [](hid_t f, hsize_t r, const char* path) {
        std::int64_t first = 0;
        h5::read_block(f, "/replicas/particle_offset", H5T_NATIVE_INT64, {r}, {1}, &first);
        double n = 0;
        h5::read_block(f, "/replicas/N", H5T_NATIVE_DOUBLE, {r}, {1}, &n);
        std::vector<double> out(static_cast<std::size_t>(n));
        h5::read_block(f, path, H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(first)}, {out.size()}, out.data());
        return out;
    };
    for (const char* path : {"/final/x", "/final/y", "/final/diameter"})
        if (!same(disks(fa.get(), ra, path), disks(fb.get(), rb, path))) return path;
    // Configuration frames, where either archive keeps them.
    const bool frames_a = h5::exists(fa.get(), "/frames/strain"), frames_b = h5::exists(fb.get(), "/frames/strain");
    if (frames_a != frames_b) return "/frames";
    if (frames_a) {
        for (const char* path : {"/frames/strain", "/frames/box_strain"})
            if (!same(row(fa.get(), path, ra), row(fb.get(), path, rb))) return path;
        const std::vector<double> strains = row(fa.get(), "/frames/strain", ra);
        const auto frame = [](hid_t f, hsize_t r, const char* path, hsize_t k) {
            std::int64_t first = 0;
            h5::read_block(f, "/replicas/particle_offset", H5T_NATIVE_INT64, {r}, {1}, &first);
            double n = 0;
            h5::read_block(f, "/replicas/N", H5T_NATIVE_DOUBLE, {r}, {1}, &n);
            std::vector<double> out(static_cast<std::size_t>(n));
            h5::read_block(f, path, H5T_NATIVE_DOUBLE, {k, static_cast<hsize_t>(first)}, {1, out.size()}, out.data());
            return out;
        };
        for (hsize_t k = 0; k < strains.size(); ++k) {
            if (std::isnan(strains[k])) continue;
            for (const char* path : {"/frames/x", "/frames/y"})
                if (!same(frame(fa.get(), ra, path, k), frame(fb.get(), rb, path, k))) return path;
        }
    }
    std::int64_t ea = 0, eb = 0;
    h5::read_block(fa.get(), "/replicas/force_evaluations", H5T_NATIVE_INT64, {ra}, {1}, &ea);
    h5::read_block(fb.get(), "/replicas/force_evaluations", H5T_NATIVE_INT64, {rb}, {1}, &eb);
    if (ea != eb) return "/replicas/force_evaluations";
    return "";
}

}  // namespace jamsim
