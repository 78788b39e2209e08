#pragma once
// Checks shared by the commands' options: a file path that names a file (one that can be
// made), a count >= 1.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <chrono>
#include <string>
#include <thread>
#include <utility>

#include <CLI/CLI.hpp>

#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/core/parse_number.hpp"

namespace jamsim::app {

/// Refuses an empty path (`-o ""`, an unset shell variable) before any work: a replica would
/// otherwise run to the end and fail at its write, and `merge -o ""` take its first input as
/// the output. CLI11 puts the option's name before the message ("--output: value '' ...").
inline CLI::Validator nonempty_path() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
            return v.empty() ? "value '' is not allowed: the path of a file (an empty path names none)" : "";
        },
        "FILE");
}

/// Decimal digits alone: strtoll also took " 16" and "+16" (and --threads refused them).
inline bool digits_only(const std::string& v) {
    return !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
}

/// A whole number >= 1 of `what` ("replicas", "ranks"); CLI11's own PositiveNumber printed
/// "Value 0 not in range 0.000000 to 1.79769e+308" (300 digits of it).
inline CLI::Validator count_at_least_one(const std::string& what) {
    return CLI::Validator(
        [what](std::string& v) -> std::string {
            char* end = nullptr;
            errno = 0;
            const long long n = std::strtoll(v.c_str(), &end, 10);
            return digits_only(v) && *end == '\0' && n >= 1 && errno != ERANGE
                       ? ""
                       : "value " + v + " is not allowed: a whole number of " + what + " >= 1";
        },
        "COUNT >= 1");
}

/// A whole number of `what` from 1 to `most` (CLI11's Range said "Value 0 not in range 1 to
/// 1000000").
inline CLI::Validator count_from_one_to(const std::string& what, long long most) {
    return CLI::Validator(
        [what, most](std::string& v) -> std::string {
            char* end = nullptr;
            errno = 0;
            const long long n = std::strtoll(v.c_str(), &end, 10);
            return digits_only(v) && *end == '\0' && n >= 1 && n <= most && errno != ERANGE
                       ? ""
                       : "value " + v + " is not allowed: a whole number of " + what + " from 1 to " +
                             std::to_string(most);
        },
        "COUNT >= 1");
}

/// A number written in decimal, as in a campaign file: CLI11 (strtod) also read hexadecimal
/// (--phi 0x1p-1 as 0.5) and skipped leading white space. The range is the option's own check.
inline CLI::Validator decimal_number() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
            std::string_view digits = v;
            if (digits.starts_with('+') && digits.size() > 1 && digits[1] != '-') digits.remove_prefix(1);
            double ignored = 0.0;
            if (parse_whole_text(digits, ignored)) return "";
            return "value '" + v + "' is not allowed: " +
                   (decimal_beyond_double(v) ? std::string(kDoubleRangeWords) : std::string("a number in decimal"));
        },
        "NUMBER");
}

/// "" when the file name of `p` leaves room, in its folder's limit on names (NAME_MAX, 255
/// on most filesystems), for the temporary written beside it (NAME.XXXXXX.tmp); else what is
/// allowed. A longer name ran the whole replica and failed only when writing it.
inline std::string name_fits_folder(const std::filesystem::path& p) {
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
    const long most = ::pathconf(dir.c_str(), _PC_NAME_MAX);
    const std::size_t length = p.filename().string().size(), temporary = std::strlen(".XXXXXX.tmp");
    if (most <= 0 || length + temporary <= static_cast<std::size_t>(most)) return "";
    return "a file name of at most " + std::to_string(static_cast<std::size_t>(most) - temporary) +
           " bytes in that folder (this one has " + std::to_string(length) + ")";
}

/// The ranks a launcher (mpirun, srun) started this process among, from its environment
/// (1 without one), and this process's rank among them.
inline std::pair<long, long> launcher_ranks() {
    const auto number = [](std::initializer_list<const char*> names) -> long {
        for (const char* name : names)
            if (const char* text = std::getenv(name); text && *text) return std::strtol(text, nullptr, 10);
        return -1;
    };
    // Not Slurm's own SLURM_NTASKS and the like: a batch script or an allocation's shell has them
    // without being one of many ranks.
    const long size = number({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"});
    const long rank = number({"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"});
    return {size > 1 ? size : 1, rank > 0 ? rank : 0};
}

/// A command that runs as one process (replica, minimize, export) started by `mpirun -n 2`:
/// every rank ran it, wrote the same output and, for export, all but one then refused it as
/// existing. One message (from rank 0), exit 2 on every rank.
inline void refuse_more_than_one_process(const std::string& command) {
    const auto [size, rank] = launcher_ranks();
    if (size <= 1) return;
    if (rank == 0)
        std::fprintf(stderr, "%s: run it as one process (not mpirun -n %ld: every rank would write the same output)\n",
                     command.c_str(), size);
    else  // after rank 0 (the launcher kills the rest of the job when the first rank ends)
        std::this_thread::sleep_for(std::chrono::seconds(2));
    throw CLI::RuntimeError(2);
}

/// A whole number in decimal digits that fits 64 bits: no sign (CLI11 read "-1" into an
/// unsigned option as 2^64 - 1), no hexadecimal, no exponent.
inline CLI::Validator whole_number() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
            // At most 2^63 - 1, what a campaign (TOML) and an archive's parameter columns hold.
            const bool digits = !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
            errno = 0;
            if (digits) (void)std::strtoll(v.c_str(), nullptr, 10);
            return digits && errno != ERANGE
                       ? ""
                       : "value '" + v + "' is not allowed: a whole number from 0 to 9223372036854775807 in decimal";
        },
        "INTEGER >= 0");
}

/// "" when `path` names a file that can be made: in an existing directory where a file can
/// be created (tried: access() passes for root where nothing can be, /proc or a read-only
/// mount), not a directory itself; else what is allowed and why not, for the command's
/// refusal before any work (a write that fails only after the run loses it).
inline std::string writable_new_file(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (fs::is_directory(p, ec) || p.filename().empty()) return "a file name, not a directory";
    // The output is written beside and renamed into place, which replaces a link (a dangling
    // one, or a loop) instead of writing what it names.
    if (fs::is_symlink(fs::symlink_status(p, ec)))
        return "a file's own path, not a symbolic link ('" + path +
               "' is one: the output would replace the link, not write what it names)";
    if (const std::string why = odd_file_name(path); !why.empty()) return why;
    if (!fs::is_directory(dir, ec)) return "a file in an existing directory ('" + dir.string() + "' does not exist)";
    if (::access(dir.c_str(), W_OK) != 0)
        return "a file in a writable directory ('" + dir.string() + "' is not writable)";
    if (const std::string why = name_fits_folder(p); !why.empty()) return why;
    std::string probe = (dir / ".jamsim-probe-XXXXXX").string();
    const int fd = ::mkstemp(probe.data());
    if (fd < 0)
        return "a file in a directory where files can be made ('" + dir.string() + "': " + std::strerror(errno) + ")";
    ::close(fd);
    ::unlink(probe.c_str());
    return "";
}

}  // namespace jamsim::app
