// Diagnosis of a file given as a campaign archive, before anything opens it for real: each
// kind of bad file gets its own sentence instead of HDF5's "open failed".
#include "jamsim/archive/archive_file_check.hpp"

#include "archive_detail.hpp"

#include <unistd.h>

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/core/invisible_text.hpp"
#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/io/hdf5.hpp"
#include "jamsim/io/lammps_data.hpp"
#include "jamsim/io/little_endian.hpp"
#include "jamsim/io/read_deadline.hpp"

namespace jamsim {

namespace archive_detail {

/// A dataset's shape and HDF5 type class (H5T_INTEGER, H5T_FLOAT, H5T_STRING, ...).
DatasetForm dataset_form(hid_t file, const std::string& path) {
    const h5::Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "open " + path);
    const h5::Handle space(H5Dget_space(set.get()), H5Sclose, "dataspace of " + path);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    h5::check(rank, "rank of " + path);
    DatasetForm form{std::vector<hsize_t>(static_cast<std::size_t>(rank)), H5T_NO_CLASS};
    h5::check(H5Sget_simple_extent_dims(space.get(), form.dims.data(), nullptr), "shape of " + path);
    const h5::Handle type(H5Dget_type(set.get()), H5Tclose, "type of " + path);
    form.type = H5Tget_class(type.get());
    if (form.type == H5T_NO_CLASS) throw h5::Error("HDF5: type class of " + path + " failed");
    return form;
}

std::string shape_text(const std::vector<hsize_t>& dims) {
    if (dims.empty()) return "a scalar";
    std::string text;
    for (std::size_t k = 0; k < dims.size(); ++k) text += (k ? " x " : "") + std::to_string(dims[k]);
    if (dims.size() == 1) return text + (dims[0] == 1 ? " entry" : " entries");
    return text;
}

}  // namespace archive_detail

using archive_detail::dataset_form;
using archive_detail::shape_text;

namespace {

constexpr std::array<unsigned char, 8> kSignature = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// Where the HDF5 superblock says the file ends (base address + end-of-file address), in
/// bytes, when the superblock can be read: HDF5 looks for it at 0, 512, 1024, 2048, ...
/// (File Format Specification, "Format Signature and Version Information").
struct Superblock {
    bool found = false;
    std::optional<std::uint64_t> end;  ///< bytes the file must have
};

Superblock read_superblock(std::ifstream& in, std::uint64_t size) {
    Superblock sb;
    for (std::uint64_t at = 0; at + kSignature.size() <= size; at = at == 0 ? 512 : 2 * at) {
        std::string head(96, '\0');
        in.clear();
        in.seekg(static_cast<std::streamoff>(at));
        in.read(head.data(), static_cast<std::streamsize>(head.size()));
        head.resize(static_cast<std::size_t>(in.gcount()));
        if (head.size() < kSignature.size() || std::memcmp(head.data(), kSignature.data(), kSignature.size()) != 0)
            continue;
        sb.found = true;
        const auto version = static_cast<unsigned char>(head.size() > 8 ? head[8] : 0xff);
        // Offsets of the size-of-offsets byte and of the base address per version.
        std::size_t offsets_at = 0, base_at = 0, eof_index = 0;
        if (version == 0 || version == 1) {
            offsets_at = 13;
            base_at = version == 0 ? 24 : 28;
            eof_index = 2;  // base, free-space info, end of file, driver info
        } else if (version == 2 || version == 3) {
            offsets_at = 9;
            base_at = 12;
            eof_index = 2;  // base, superblock extension, end of file, root object header
        } else {
            return sb;
        }
        if (head.size() <= offsets_at) return sb;
        const auto o = static_cast<std::size_t>(static_cast<unsigned char>(head[offsets_at]));
        if (o < 2 || o > 8 || head.size() < base_at + (eof_index + 1) * o) return sb;
        const std::uint64_t base = little_endian(head, base_at, o);
        const std::uint64_t eof = little_endian(head, base_at + eof_index * o, o);
        sb.end = base + eof;
        return sb;
    }
    return sb;
}

/// A root attribute's presence.
bool has_attribute(hid_t file, const char* name) {
    const htri_t r = H5Aexists(file, name);
    if (r < 0) throw h5::Error(std::string("HDF5: query of attribute '") + name + "' failed");
    return r > 0;
}

/// A link's presence.
bool has_link(hid_t file, const char* name) {
    const htri_t r = H5Lexists(file, name, H5P_DEFAULT);
    if (r < 0) throw h5::Error(std::string("HDF5: query of '") + name + "' failed");
    return r > 0;
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// The names of the links in `group` (an absolute path), in name order.
std::vector<std::string> link_names(hid_t file, const std::string& group) {
    const h5::Handle g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose, "open " + group);
    H5G_info_t info{};
    h5::check(H5Gget_info(g.get(), &info), "list " + group);
    std::vector<std::string> names;
    for (hsize_t k = 0; k < info.nlinks; ++k) {
        const ssize_t length = H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
        h5::check(static_cast<hid_t>(length), "list " + group);
        std::string name(static_cast<std::size_t>(length) + 1, '\0');
        h5::check(static_cast<hid_t>(H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(),
                                                        name.size(), H5P_DEFAULT)),
                  "list " + group);
        name.resize(static_cast<std::size_t>(length));
        names.push_back(name);
    }
    return names;
}

/// The archive's datasets against its n_replicas: every /replicas column and /final/box_side,
/// box_strain of n entries, numbers (failure_reason text); /timeseries and /correlation each
/// of one shape with n rows; /frames' x and y of one shape, its strains of one shape with n
/// rows; /final/x, y, diameter of one length; every status 0 to 3. "" when they agree, else
/// what a damaged or hand-edited file got wrong (reading or resuming it would fail half-way,
/// or misread its replicas).
std::string check_layout(hid_t f) {
    if (!has_attribute(f, "n_replicas")) return "it has no n_replicas attribute";
    const std::int64_t stored = h5::read_int64_attribute(f, "n_replicas");
    if (stored < 0) return "n_replicas is " + std::to_string(stored);
    const auto n = static_cast<hsize_t>(stored);
    for (const char* group : {"/timeseries", "/final"})
        if (!has_link(f, group)) return std::string("it has no ") + group;
    const std::string rows = " (n_replicas is " + std::to_string(n) + ")";
    for (const std::string& name : link_names(f, "/replicas")) {
        const std::string path = "/replicas/" + name;
        const auto [dims, c] = dataset_form(f, path);
        if (dims != std::vector<hsize_t>{n}) return path + " has " + shape_text(dims) + rows;
        const bool text = name == "failure_reason";
        if (text ? c != H5T_STRING : (c != H5T_INTEGER && c != H5T_FLOAT))
            return path + (text ? " is not text" : " is not numbers");
    }
    const auto status = h5::read_all<std::int8_t>(f, "/replicas/status", H5T_NATIVE_INT8);
    for (std::size_t r = 0; r < status.size(); ++r)
        if (status[r] < 0 || status[r] > 3)
            return "/replicas/status[" + std::to_string(r) + "] is " + std::to_string(status[r]) +
                   " (0 pending, 1 running, 2 done, 3 failed)";
    // Groups whose datasets share one shape; `first` rows must be n when `per_replica`.
    auto one_shape = [&](const std::string& group, const std::vector<std::string>& names,
                         bool per_replica) -> std::string {
        std::vector<hsize_t> shape;
        std::string first;
        for (const std::string& name : names) {
            const std::string path = group + "/" + name;
            const auto [dims, type] = dataset_form(f, path);
            if (type != H5T_FLOAT) return path + " is not floating-point numbers";
            if (per_replica && (dims.size() != 2 || dims[0] != n))
                return path + " is " + shape_text(dims) + ", not n_replicas rows" + rows;
            if (first.empty()) {
                shape = dims;
                first = path;
            } else if (dims != shape) {
                return path + " is " + shape_text(dims) + " where " + first + " is " + shape_text(shape);
            }
        }
        return "";
    };
    if (std::string bad = one_shape("/timeseries", link_names(f, "/timeseries"), true); !bad.empty()) return bad;
    if (has_link(f, "/correlation"))
        if (std::string bad = one_shape("/correlation", link_names(f, "/correlation"), true); !bad.empty()) return bad;
    if (has_link(f, "/frames")) {  // x, y: frames x disks; strain, box_strain: replicas x frames
        if (std::string bad = one_shape("/frames", {"x", "y"}, false); !bad.empty()) return bad;
        if (std::string bad = one_shape("/frames", {"strain", "box_strain"}, true); !bad.empty()) return bad;
    }
    for (const char* name : {"box_side", "box_strain"}) {
        const std::string path = std::string("/final/") + name;
        if (!h5::exists(f, path)) return "it has no " + path;
        if (const auto dims = h5::dataset_shape(f, path); dims != std::vector<hsize_t>{n})
            return path + " has " + shape_text(dims) + rows;
    }
    for (const char* name : {"x", "y", "diameter"})
        if (!h5::exists(f, std::string("/final/") + name)) return std::string("it has no /final/") + name;
    if (std::string bad = one_shape("/final", {"x", "y", "diameter"}, false); !bad.empty()) return bad;
    return "";
}

std::string number_text(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    return text;
}

/// The counts that place each replica's data: N whole numbers from 1, particle_offset their
/// running sum from 0 (disks end to end in /final), n_samples whole numbers up to the columns
/// of /timeseries, rows_written up to n_samples. "" when they agree, else the first that does
/// not (a hand-edited N = nan or offset = 1e12 met HDF5 or the reader half-way, or was copied
/// on by merge and export). Called after check_layout's shapes.
std::string check_counts(hid_t f) {
    const auto whole = [](double v, double low, double high) { return v >= low && v <= high && v == std::floor(v); };
    if (!h5::exists(f, "/replicas/N")) return "it has no /replicas/N";
    const std::vector<double> n = h5::read_dataset(f, "/replicas/N");
    const std::vector<hsize_t> final_shape = h5::dataset_shape(f, "/final/x");
    if (final_shape.size() != 1) return "/final/x is " + shape_text(final_shape) + ", not one list of disks";
    const auto disks = static_cast<double>(final_shape.front());
    for (std::size_t r = 0; r < n.size(); ++r)
        if (!whole(n[r], 1, disks))
            return "/replicas/N[" + std::to_string(r) + "] is " + number_text(n[r]) +
                   " (a whole number of disks from 1 to the " + number_text(disks) + " of /final/x)";
    if (h5::exists(f, "/replicas/particle_offset")) {
        const auto offset = h5::read_all<std::int64_t>(f, "/replicas/particle_offset", H5T_NATIVE_INT64);
        double before = 0;
        for (std::size_t r = 0; r < offset.size(); before += n[r], ++r)
            if (static_cast<double>(offset[r]) != before)
                return "/replicas/particle_offset[" + std::to_string(r) + "] is " + std::to_string(offset[r]) +
                       " where the disks of the replicas before it add up to " + number_text(before);
        if (before != disks)
            return "the replicas' N add up to " + number_text(before) + " disks where /final/x has " +
                   number_text(disks);
    }
    const std::vector<std::string> series = link_names(f, "/timeseries");
    if (series.empty() || !h5::exists(f, "/replicas/n_samples")) return "";
    const auto columns = static_cast<double>(h5::dataset_shape(f, "/timeseries/" + series.front()).at(1));
    const std::vector<double> samples = h5::read_dataset(f, "/replicas/n_samples");
    for (std::size_t r = 0; r < samples.size(); ++r)
        if (!whole(samples[r], 0, columns))
            return "/replicas/n_samples[" + std::to_string(r) + "] is " + number_text(samples[r]) +
                   " (a whole number of rows from 0 to the " + number_text(columns) + " columns of /timeseries)";
    if (h5::exists(f, "/replicas/rows_written")) {
        const auto rows = h5::read_all<std::int64_t>(f, "/replicas/rows_written", H5T_NATIVE_INT64);
        for (std::size_t r = 0; r < rows.size(); ++r)
            if (rows[r] < 0 || static_cast<double>(rows[r]) > samples[r])
                return "/replicas/rows_written[" + std::to_string(r) + "] is " + std::to_string(rows[r]) +
                       " (from 0 to its n_samples, " + number_text(samples[r]) + ")";
    }
    return "";
}

/// "2026-11-29T09:01:35Z", as utc_now writes it (digits where it has digits).
bool is_utc_stamp(const std::string& text) {
    static constexpr std::string_view kForm = "dddd-dd-ddTdd:dd:ddZ";
    if (text.size() != kForm.size()) return false;
    for (std::size_t i = 0; i < text.size(); ++i)
        if (kForm[i] == 'd' ? !std::isdigit(static_cast<unsigned char>(text[i])) : text[i] != kForm[i]) return false;
    return true;
}

/// The bookkeeping a run writes beside the data: each replica's rank (-1 before it runs),
/// progress (0 to 1), force evaluations (from 0), threads and wall seconds, the root's
/// n_ranks and its time stamps. jamsim computes nothing from them, but `status`, the
/// reports and merge copy them on, so a hand-edited progress of 5 or rank of -3 reached
/// users as fact. "" when each is in its range, else the first that is not.
std::string check_bookkeeping(hid_t f) {
    constexpr double kMostRanks = 1 << 20;  // as run --ranks
    const auto column = [f](const char* name) { return h5::read_dataset(f, std::string("/replicas/") + name); };
    const auto entry = [](const char* name, std::size_t r, double v, const char* allowed) {
        return std::string("/replicas/") + name + "[" + std::to_string(r) + "] is " + number_text(v) + " (" + allowed +
               ")";
    };
    struct Range {
        const char* name;
        double low, high;
        bool nan_allowed, whole;
        const char* allowed;
    };
    static constexpr Range kRanges[] = {
        {"rank", -1, kMostRanks - 1, false, true, "the MPI rank that ran it, from 0, or -1 before it runs"},
        {"progress", 0, 1, false, false, "the fraction of its steps done, from 0 to 1"},
        {"force_evaluations", 0, 9e18, false, true, "a whole count from 0"},
        {"threads", 0, kMostRanks, false, false, "its mean threads, from 0 (0: not recorded)"},
        {"wall_seconds", 0, 1e12, true, false, "its wall time in seconds from 0, or nan before it runs"}};
    for (const Range& range : kRanges) {
        if (!h5::exists(f, std::string("/replicas/") + range.name)) continue;
        const std::vector<double> values = column(range.name);
        for (std::size_t r = 0; r < values.size(); ++r) {
            const double v = values[r];
            if (std::isnan(v) && range.nan_allowed) continue;
            if (!(v >= range.low && v <= range.high) || (range.whole && v != std::floor(v)))
                return entry(range.name, r, v, range.allowed);
        }
    }
    if (has_attribute(f, "n_ranks"))
        if (const std::int64_t ranks = h5::read_int64_attribute(f, "n_ranks");
            ranks < 0 || static_cast<double>(ranks) > kMostRanks)
            return "its attribute n_ranks is " + std::to_string(ranks) + " (the ranks of its last run, from 0 to 2^20)";
    if (has_attribute(f, "created"))
        if (const std::string created = h5::read_string_attribute(f, "created"); !is_utc_stamp(created))
            return "its attribute created is '" + created + "' (a UTC time such as 2026-11-29T09:01:35Z)";
    for (const char* stamp : archive_detail::kStampAttributes)
        if (has_attribute(f, stamp))
            if (const std::string text = h5::read_string_attribute(f, stamp); !text.empty() && !is_utc_stamp(text))
                return std::string("its attribute ") + stamp + " is '" + text +
                       "' (empty or a UTC time such as 2026-11-29T09:01:35Z)";
    return "";
}

/// The fingerprint version ("jamsim campaign v7") at the start of a fingerprint.
std::string fingerprint_version(const std::string& fingerprint) {
    const std::string prefix = "jamsim campaign v";
    if (fingerprint.rfind(prefix, 0) != 0) return "";
    return fingerprint.substr(0, fingerprint.find(' ', prefix.size()));
}

/// A single-replica file's root: the identity and model attributes of jamsim replica.
bool is_replica_root(hid_t f) { return has_attribute(f, "identity") && has_attribute(f, "model"); }

/// The root attributes that jamsim reads, of the class it writes them with (a hand-edited
/// n_ranks of text made `status` fail with an HDF5 read error); "" when they are.
std::string check_attribute_classes(hid_t f) {
    static constexpr const char* kText[] = {"campaign",     "spec_path",   "spec_text",    "spec_fingerprint",
                                            "code_version", "run_started", "run_finished", "merged",
                                            "extended",     "grown",       "created"};
    static constexpr const char* kInteger[] = {"layout_version", "n_replicas", "n_ranks"};
    const auto class_of = [f](const char* name) {
        const h5::Handle attr(H5Aopen(f, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
        const h5::Handle type(H5Aget_type(attr.get()), H5Tclose, std::string("type of attribute ") + name);
        const h5::Handle space(H5Aget_space(attr.get()), H5Sclose, std::string("space of attribute ") + name);
        return std::pair{H5Tget_class(type.get()), H5Sget_simple_extent_npoints(space.get())};
    };
    for (const char* name : kText)
        if (has_attribute(f, name) && class_of(name).first != H5T_STRING)
            return std::string("its attribute ") + name + " is not text";
    for (const char* name : kInteger)
        if (has_attribute(f, name)) {
            const auto [cls, points] = class_of(name);
            if (cls != H5T_INTEGER || points != 1) return std::string("its attribute ") + name + " is not one integer";
        }
    return "";
}

/// Reads every text attribute of every object once (the root's, and the units and
/// descriptions of the datasets). Each variable-length one lives in a global heap collection,
/// and HDF5 loops on a damaged collection; read here, under the read deadline, a later reader
/// (jamsim's own, h5py's) never meets one first.
void read_every_text_attribute(hid_t f) {
    const H5A_operator2_t read = [](hid_t object, const char* name, const H5A_info_t*, void*) -> herr_t {
        const hid_t attr = H5Aopen(object, name, H5P_DEFAULT);
        if (attr < 0) return 0;
        const hid_t type = H5Aget_type(attr);
        const bool text = type >= 0 && H5Tget_class(type) == H5T_STRING;
        if (type >= 0) H5Tclose(type);
        H5Aclose(attr);
        if (text) try {
                (void)h5::read_string_attribute(object, name);
            } catch (const h5::Error&) {}  // a damaged attribute: the checks below say what is wrong
        return 0;
    };
    const H5O_iterate_t visit = [](hid_t root, const char* name, const H5O_info_t*, void* op) -> herr_t {
        const hid_t object = H5Oopen(root, name, H5P_DEFAULT);
        if (object < 0) return 0;  // the checks below say what is wrong
        H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, *static_cast<H5A_operator2_t*>(op), nullptr);
        H5Oclose(object);
        return 0;
    };
    H5A_operator2_t op = read;
    H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_NATIVE, visit, &op, H5O_INFO_BASIC);  // the root ("."), then the rest
}

/// The checks that need HDF5 to open the file; "" when it is a usable archive.
std::string check_contents(const std::string& path) {
    const h5::Handle file = h5::open_unlocked_readonly(path);
    const hid_t f = file.get();
    read_every_text_attribute(f);
    const bool archive = has_attribute(f, "spec_fingerprint") && has_attribute(f, "campaign");
    if (!archive) {
        if (is_replica_root(f))
            return quoted(path) + " is a single-replica file of jamsim replica, not a campaign "
                                  "archive (jamsim run writes those)";
        return quoted(path) + " is an HDF5 file but not a jamsim campaign archive (it has no "
                              "campaign and spec_fingerprint attributes)";
    }
    if (const std::string bad = check_attribute_classes(f); !bad.empty())
        return quoted(path) + " is damaged: " + bad + "; jamsim writes no such archive (a hand-edited or broken copy?)";
    const std::string written_by = has_attribute(f, "code_version")
                                       ? " (written by jamsim " + h5::read_string_attribute(f, "code_version") + ")"
                                       : "";
    if (!has_attribute(f, "layout_version"))
        return quoted(path) + " has an older archive layout without a layout_version" + written_by +
               "; this jamsim reads layout " + std::to_string(kArchiveLayoutVersion) + ": read it with that version";
    const std::int64_t layout = h5::read_int64_attribute(f, "layout_version");
    if (layout != kArchiveLayoutVersion)
        return quoted(path) + " has archive layout " + std::to_string(layout) + written_by +
               "; this jamsim reads layout " + std::to_string(kArchiveLayoutVersion) +
               ": read it with the jamsim that wrote it";
    const std::string stored = fingerprint_version(h5::read_string_attribute(f, "spec_fingerprint"));
    const std::string current = fingerprint_version(fingerprint(CampaignSpec{}));
    if (stored != current)
        return quoted(path) + " was written by another version of jamsim (" +
               (stored.empty() ? "an unknown fingerprint" : stored) + "; this one writes " + current + ")" +
               written_by +
               ": its results mean something else (start a new "
               "archive)";
    if (!has_link(f, "/replicas") || !has_link(f, "/replicas/status"))
        return quoted(path) + " is damaged: a jamsim campaign archive without /replicas/status";
    for (const auto& check : {check_layout, check_counts, check_bookkeeping, archive_detail::campaign_mismatch})
        if (const std::string bad = check(f); !bad.empty())
            return quoted(path) + " is damaged: " + bad +
                   "; jamsim writes no such archive (a hand-edited or broken copy?)";
    return "";
}

}  // namespace

std::string diagnose_archive_file(const std::string& path) {
    if (path.empty()) return "an empty path is not a campaign archive";
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return quoted(path) + " does not exist";
        return quoted(path) + " cannot be examined: " + std::strerror(errno);
    }
    if (S_ISDIR(st.st_mode)) return quoted(path) + " is a directory, not a campaign archive";
    if (const std::string marker = Archive::creation_marker(path); ::access(marker.c_str(), F_OK) == 0)
        return quoted(path) + " is being created, or a kill interrupted its creation ('" + marker +
               "' is beside it): a jamsim run or merge to it makes it anew";
    if (!S_ISREG(st.st_mode)) return quoted(path) + " is not a regular file";
    const auto size = static_cast<std::uint64_t>(st.st_size);
    std::ifstream in(path, std::ios::binary);
    if (!in) return quoted(path) + " cannot be read: " + std::strerror(errno);
    if (size == 0) return quoted(path) + " is empty (0 bytes), not a campaign archive";
    const Superblock sb = read_superblock(in, size);
    if (!sb.found)
        return quoted(path) + " is not an HDF5 file (no HDF5 signature in its " + std::to_string(size) +
               " bytes), so not a campaign archive";
    if (sb.end && *sb.end > size)
        return quoted(path) + " is truncated: its HDF5 superblock says " + std::to_string(*sb.end) +
               " bytes, the file has " + std::to_string(size) + " (an interrupted copy or a full disk?)";
    h5::quiet_errors();
    try {
        const ReadDeadline deadline(path, read_deadline_seconds());
        return check_contents(path);
    } catch (const h5::Error& e) {
        return quoted(path) + " is a damaged HDF5 file (it has the HDF5 signature but " + e.what() + ")";
    }
}

std::string odd_file_name(const std::string& path) {
    if (std::any_of(path.begin(), path.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
        return "a path without line breaks or control characters";
    if (const std::string code = invisible_character(path); !code.empty())
        return "a path without invisible characters (it holds " + code + ")";
    if (path == "-") return "a file name, not '-' (jamsim writes its files to disk, never to standard output)";
    const std::string name = std::filesystem::path(path).filename().string();
    const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    if (name.empty() || (!blank(name.front()) && !blank(name.back()))) return "";
    return "a file name that neither starts nor ends with white space ('" + name +
           "': a quoting mistake in the command line or campaign?)";
}

std::string output_path_problem(const std::string& path) {
    // A shell expands ~ before jamsim sees it; in a campaign file (or quoted) it made a
    // folder named ~ in the working directory.
    if (path.starts_with("~")) {
        const char* home = std::getenv("HOME");
        const std::string hint =
            path.starts_with("~/") && home && *home ? " (" + std::string(home) + path.substr(1) + " here)" : "";
        return "a path without a leading '~', which only a shell expands: write the home folder out" + hint;
    }
    const std::filesystem::path p(path);
    const std::string name = p.filename().string();
    if (name.empty() || name == "." || name == "..")
        return "a file path, not a folder ('" + path + "' ends in '" + (name.empty() ? "/" : name) + "')";
    if (const std::string why = odd_file_name(path); !why.empty()) return why;
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        const int stat_error = errno;
        // A symbolic link to a file that does not exist is followed when the file is made;
        // one into a folder that does not exist made HDF5's create fail without a reason.
        if (std::error_code ec; stat_error == ENOENT && std::filesystem::is_symlink(p, ec)) {
            const std::filesystem::path target = std::filesystem::read_symlink(p, ec);
            const std::filesystem::path folder =
                (target.is_absolute() ? target : p.parent_path() / target).parent_path();
            if (!ec && !folder.empty() && !std::filesystem::is_directory(folder, ec))
                return "a file that can be made: '" + path + "' is a symbolic link to '" + target.string() +
                       "', whose folder '" + folder.string() + "' does not exist";
        }
        if (stat_error == ENOENT || stat_error == ENOTDIR) return "";  // the folder checks say why
        return "'" + path + "' cannot be examined: " + std::strerror(stat_error);
    }
    if (!S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))  // a FIFO blocked the run's open() for good
        return "a regular file: " + not_a_regular_file(path);
    if (S_ISREG(st.st_mode) && (st.st_mode & 0222) == 0) {
        char mode[8];
        std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
        return "a writable file: '" + path + "' is read-only (mode " + mode +
               "), and jamsim writes into it (chmod u+w to continue it)";
    }
    return "";
}

std::string not_a_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return "";  // missing: the readers say so
    const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                       : S_ISFIFO(st.st_mode) ? "a pipe (a FIFO or a process substitution)"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a regular file";
    return "'" + path + "' is " + kind + ", not a regular file";
}

std::string diagnose_initial_source(const std::string& path) {
    namespace fs = std::filesystem;
    if (std::error_code ec; !fs::exists(path, ec)) {
        // A loop of links was called missing by a later reader, and the run failed (exit 1).
        if (std::error_code link_ec; fs::is_symlink(fs::symlink_status(path, link_ec)))
            return quoted(path) + " is a symbolic link that leads to no file (" +
                   (ec.value() == ELOOP
                        ? std::string("a loop of links")
                        : "it names '" + fs::read_symlink(path, link_ec).string() + "', which does not exist") +
                   ")";
        if (!ec || ec.value() == ENOENT || ec.value() == ENOTDIR) return quoted(path) + " does not exist";
        return quoted(path) + " cannot be examined: " + ec.message();
    }
    if (std::string odd = not_a_regular_file(path); !odd.empty()) return odd;
    return is_hdf5_file(path) ? diagnose_archive_file(path) : "";
}

bool is_single_replica_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0) return false;
    std::ifstream in(path, std::ios::binary);
    if (!in || !read_superblock(in, static_cast<std::uint64_t>(st.st_size)).found) return false;
    h5::quiet_errors();
    try {
        const h5::Handle file = h5::open_unlocked_readonly(path);
        return is_replica_root(file.get()) && !has_attribute(file.get(), "spec_fingerprint");
    } catch (const h5::Error&) { return false; }
}

}  // namespace jamsim
