// Diagnosis of a file given as a campaign archive, before anything opens it for real: each
// kind of bad file gets its own sentence instead of HDF5's "open failed".
#include "jamsim/archive/archive_file_check.hpp"

#include <sys/stat.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>

#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/io/hdf5.hpp"

namespace jamsim {

namespace {

constexpr std::array<unsigned char, 8> kSignature = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// Little-endian unsigned integer of `bytes` bytes at `at` (HDF5 stores addresses so).
std::uint64_t little_endian(const std::string& data, std::size_t at, std::size_t bytes) {
    std::uint64_t v = 0;
    for (std::size_t k = 0; k < bytes; ++k)
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(data[at + k])) << (8 * k);
    return v;
}

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

/// The fingerprint version ("jamsim campaign v7") at the start of a fingerprint.
std::string fingerprint_version(const std::string& fingerprint) {
    const std::string prefix = "jamsim campaign v";
    if (fingerprint.rfind(prefix, 0) != 0) return "";
    return fingerprint.substr(0, fingerprint.find(' ', prefix.size()));
}

/// The checks that need HDF5 to open the file; "" when it is a usable archive.
std::string check_contents(const std::string& path) {
    const h5::Handle file = h5::open_unlocked_readonly(path);
    const hid_t f = file.get();
    const bool archive = has_attribute(f, "spec_fingerprint") && has_attribute(f, "campaign");
    if (!archive) {
        if (has_attribute(f, "identity") && has_attribute(f, "model"))
            return quoted(path) + " is a single-replica file of jamsim replica, not a campaign "
                                  "archive (jamsim run writes those)";
        return quoted(path) + " is an HDF5 file but not a jamsim campaign archive (it has no "
                              "campaign and spec_fingerprint attributes)";
    }
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
        return check_contents(path);
    } catch (const h5::Error& e) {
        return quoted(path) + " is a damaged HDF5 file (it has the HDF5 signature but " + e.what() + ")";
    }
}

}  // namespace jamsim
