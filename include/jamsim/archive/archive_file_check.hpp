#pragma once
// What is wrong with a file given as a campaign archive, in words: missing, a directory,
// empty, not HDF5, truncated, not a jamsim campaign archive, another layout or version.
#include <cstdint>
#include <string>

namespace jamsim {

/// The archive layout this jamsim reads and writes: the root attribute layout_version that
/// Archive::create records (4: final configurations end to end, bulk datasets unfilled).
inline constexpr std::int64_t kArchiveLayoutVersion = 4;

/// "" when `path` opens as a jamsim campaign archive of this layout and fingerprint version;
/// otherwise one sentence naming the file and what it is ("'x.h5' is empty (0 bytes): ..."),
/// for `jamsim status`, `run` and `merge` to print before they touch it. Serial, read-only,
/// HDF5 file locking off (a running campaign may hold the file); HDF5's error stack is not
/// printed. Never throws for a bad file.
std::string diagnose_archive_file(const std::string& path);

/// For a [run] initial or --initial source: "" when `path` is not an HDF5 file (a LAMMPS
/// data file, which its reader checks) or opens as a campaign archive; else
/// diagnose_archive_file's sentence (a single-replica file, an export, a damaged archive).
std::string diagnose_initial_source(const std::string& path);
/// "" for a regular file or a path that does not exist; else "'PATH' is a pipe (...), not a
/// regular file" (a FIFO blocked open() for good, /dev/zero was read into memory).
std::string not_a_regular_file(const std::string& path);

/// For an archive jamsim is to write (run's output, merge's -o): "" when `path` names a file
/// that may be made or written; else why not, without the key: a path ending in '/' (a
/// folder), one that cannot be examined (a loop of symbolic links), an existing file that is
/// read-only (no write bit: kept even for root, who may write it anyway).
std::string output_path_problem(const std::string& path);
/// "" unless a path names a file jamsim should not make, else what is allowed: a name that
/// starts or ends with white space (`-o ' '`: a quoting mistake, which HDF5 could not create),
/// a path with a line break or another control character (it split every log line that names
/// it) or an invisible character (invisible_text.hpp), or '-' (standard output to most tools; jamsim made a file named '-').
std::string odd_file_name(const std::string& path);

/// Whether `path` is a single-replica file of jamsim replica (an HDF5 file whose root has the
/// identity and model attributes, and not a campaign archive's): the one kind of existing
/// file `jamsim replica -o` replaces. False for a missing, unreadable or damaged file; never
/// throws.
bool is_single_replica_file(const std::string& path);

}  // namespace jamsim
