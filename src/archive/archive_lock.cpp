#include "jamsim/archive/archive_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/parallel/mpi.hpp"

namespace jamsim {

namespace {

/// Lock or unlock the whole file: F_WRLCK, F_RDLCK or F_UNLCK, without waiting. Returns 0 or
/// the errno.
int set_lock(int fd, short type) {
    struct flock fl {};
    fl.l_type = type;
    fl.l_whence = SEEK_SET;
    fl.l_start = 0;
    fl.l_len = 0;  // to the end, however long
    return ::fcntl(fd, F_SETLK, &fl) == 0 ? 0 : errno;
}

bool busy(int error) { return error == EACCES || error == EAGAIN; }
/// Filesystems without record locks (some parallel filesystems mounted without them).
bool unsupported(int error) { return error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS || error == EINVAL; }

std::string holder_of(int fd) {
    char buffer[1024] = {};
    const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
    std::string text = n > 0 ? std::string(buffer, static_cast<std::size_t>(n)) : "";
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text.empty() ? "a run that has not recorded itself yet" : text;
}

std::string busy_message(const std::string& archive, const std::string& path, int fd) {
    return "'" + archive + "' is being written by " + holder_of(fd) +
           "; one run writes an archive at a time: wait for it to finish (after a kill, its ranks "
           "may take a few seconds to exit), or stop it (scancel, kill); the lock is '" +
           path + "'";
}

/// Filesystems where flock() and fcntl() locks are independent (Linux, local): there a lock
/// held on the archive file itself cannot meet MPI-IO's own byte-range locks. On network and
/// parallel filesystems (NFS, Lustre, GPFS) flock may be an fcntl lock in disguise, so the
/// archive is not locked there and the lock file alone keeps one writer.
bool local_filesystem(int fd) {
    struct statfs fs {};
    if (::fstatfs(fd, &fs) != 0) return false;
    switch (static_cast<unsigned long>(fs.f_type)) {
    case 0xEF53UL:      // ext2/3/4
    case 0x58465342UL:  // xfs
    case 0x9123683EUL:  // btrfs
    case 0x01021994UL:  // tmpfs
    case 0x794C7630UL:  // overlayfs
    case 0x2FC12FC1UL:  // zfs
        return true;
    default: return false;
    }
}

/// Why the archive file itself is held by another process ("" when it is not), tested by
/// taking flock(LOCK_EX) for a moment on `fd`.
std::string archive_held(int fd, const std::string& archive) {
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
        ::flock(fd, LOCK_UN);
        return "";
    }
    if (errno != EWOULDBLOCK) return "";  // no flock here: the lock file alone guards it
    return "'" + archive +
           "' is open in another process: a jamsim run that holds it (started through "
           "another path to the same file, or whose lock file was removed), or a program reading it "
           "with HDF5 file locking (h5py, h5dump); one run writes an archive at a time: wait for that "
           "run to finish or stop it (scancel, kill), or close the file in the other program";
}

/// Why the file open as `fd` at the lock's path is no jamsim lock file ("" when it is one:
/// empty, or written by a jamsim run or merge, stale or not): a user's file of that name would
/// be emptied and removed with the lock (it was, silently).
std::string not_a_lock(int fd, const std::string& path) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) return "";
    if (!S_ISREG(st.st_mode))
        return "the lock file '" + path +
               "' is not a regular file (a FIFO, a device, ...), which is not allowed: jamsim keeps the "
               "archive's lock in a file of that name; remove it, or write the archive under another name";
    char head[8] = {};
    if (st.st_size == 0 || (::pread(fd, head, 7, 0) == 7 && std::string_view(head, 7) == "jamsim ")) return "";
    return "'" + path + "' holds " + std::to_string(static_cast<long long>(st.st_size)) +
           " bytes that no jamsim run wrote, which is not allowed: jamsim keeps the archive's lock in a file of "
           "that name and would overwrite it; move that file away, or write the archive under another name";
}

std::string host_name() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "unknown host";
    return name;
}

}  // namespace

/// `path` still names the file open as `fd` (not removed nor replaced since it was opened).
static bool names(const std::string& path, int fd) {
    struct stat a {
    }, b{};
    return ::stat(path.c_str(), &a) == 0 && ::fstat(fd, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

std::string lock_path(const std::string& archive_path) { return archive_path + ".lock"; }

std::vector<std::string> remove_stale_mpi_locks(const std::string& archive_path) {
    namespace fs = std::filesystem;
    const fs::path archive(archive_path);
    const fs::path folder = archive.has_parent_path() ? archive.parent_path() : fs::path(".");
    const std::string base = archive.filename().string();
    // BASE[.extending|.growing]-DIGITS-DIGITS.lock
    const auto is_mpi_lock = [&](const std::string& name) {
        for (const char* suffix : {"", ".extending", ".growing"}) {
            const std::string stem = base + suffix + "-";
            if (!name.starts_with(stem) || !name.ends_with(".lock")) continue;
            const std::string middle = name.substr(stem.size(), name.size() - stem.size() - 5);
            const std::size_t dash = middle.find('-');
            const auto digits = [](std::string_view t) {
                return !t.empty() && t.find_first_not_of("0123456789") == std::string_view::npos;
            };
            if (dash != std::string::npos && digits(std::string_view(middle).substr(0, dash)) &&
                digits(std::string_view(middle).substr(dash + 1)))
                return true;
        }
        return false;
    };
    std::vector<std::string> removed;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        std::error_code gone;
        if (is_mpi_lock(name) && it->is_regular_file(gone) && fs::remove(it->path(), gone))
            removed.push_back(it->path().string());
    }
    return removed;
}

ArchiveLock ArchiveLock::acquire(MPI_Comm comm, const std::string& archive_path, const std::string& command) {
    const std::string path = lock_path(archive_path);
    const int rank = mpi::rank(comm);
    std::string error;  // rank 0's verdict: "" (locked), or why not
    int fd = -1;
    int supported = 1;
    if (rank == 0) {
        fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) {
            error = "cannot open the lock file '" + path + "': " + std::strerror(errno);
        } else if (const std::string foreign = not_a_lock(fd, path); !foreign.empty()) {
            error = foreign;
        } else if (const int e = set_lock(fd, F_WRLCK); busy(e)) {
            error = busy_message(archive_path, path, fd);
        } else if (e == 0 && !names(path, fd)) {  // removed or replaced between open and lock
            error = "the lock file '" + path +
                    "' was removed or replaced while this run took it: another run "
                    "may be starting on '" +
                    archive_path + "'; try again";
        } else if (unsupported(e)) {
            supported = 0;
            std::fprintf(stderr,
                         "jamsim: warning: the filesystem of '%s' has no file locks (%s): jamsim "
                         "cannot refuse a second run on this archive; make sure there is none\n",
                         path.c_str(), std::strerror(e));
        } else if (e != 0) {
            error = "cannot lock '" + path + "': " + std::strerror(e);
        } else {
            char started[64];
            std::snprintf(started, sizeof started, "%s", utc_now().c_str());
            const std::string holder = command + " (PID " + std::to_string(::getpid()) + " on " + host_name() + ", " +
                                       std::to_string(mpi::size(comm)) + " ranks, started " + started + ")\n";
            if (::ftruncate(fd, 0) != 0 ||
                ::pwrite(fd, holder.data(), holder.size(), 0) != static_cast<ssize_t>(holder.size()))
                error = "cannot write the lock file '" + path + "': " + std::strerror(errno);
            else if (const int d = set_lock(fd, F_RDLCK); d != 0)  // atomic downgrade
                error = "cannot share the lock '" + path + "': " + std::strerror(d);
        }
        if (!error.empty() && fd >= 0) {
            ::close(fd);
            fd = -1;
        }
    }
    mpi::broadcast(error, 0, comm);
    mpi::broadcast(supported, 0, comm);
    if (!error.empty()) throw ArchiveBusy(error);
    int e = 0;  // every other rank shares the lock rank 0 holds
    if (rank != 0 && supported) {
        fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
        e = fd < 0 ? errno : set_lock(fd, F_RDLCK);
    }
    int failed = e != 0, any = 0;
    mpi::check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
    if (any) {
        if (fd >= 0) ::close(fd);
        throw ArchiveBusy(failed ? "rank " + std::to_string(rank) + " cannot share the lock '" + path +
                                       "': " + std::strerror(e)
                                 : "another rank cannot share the lock '" + path + "'");
    }
    return ArchiveLock(comm, path, fd);
}

void ArchiveLock::check_free(const std::string& archive_path) {
    const std::string path = lock_path(archive_path);
    if (const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC); fd >= 0) {
        const int e = set_lock(fd, F_WRLCK);
        std::string message = busy(e) ? busy_message(archive_path, path, fd) : "";
        ::close(fd);  // releases what this process holds on it
        if (!message.empty()) throw ArchiveBusy(message);
    }
    // O_NONBLOCK: a FIFO in the archive's place would block open() for good (refused later).
    if (const int fd = ::open(archive_path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK); fd >= 0) {
        const std::string message = local_filesystem(fd) ? archive_held(fd, archive_path) : "";
        ::close(fd);
        if (!message.empty()) throw ArchiveBusy(message);
    }
}

void ArchiveLock::hold_archive(const std::string& archive_path) {
    std::string error;
    if (mpi::rank(comm_) == 0) {
        if (archive_fd_ >= 0) ::close(std::exchange(archive_fd_, -1));                   // an older file of that name
        const int fd = ::open(archive_path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO: no wait
        if (fd >= 0 && local_filesystem(fd)) {
            error = archive_held(fd, archive_path);
            if (error.empty() && ::flock(fd, LOCK_SH | LOCK_NB) != 0)
                error = archive_held(fd, archive_path);  // another run took it in between
        }
        if (fd >= 0 && error.empty())
            archive_fd_ = fd;
        else if (fd >= 0)
            ::close(fd);
    }
    mpi::broadcast(error, 0, comm_);
    if (!error.empty()) throw ArchiveBusy(error);
}

ArchiveLock::ArchiveLock(ArchiveLock&& other) noexcept
    : comm_(other.comm_), path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)),
      archive_fd_(std::exchange(other.archive_fd_, -1)) {}

ArchiveLock::~ArchiveLock() {
    if (fd_ >= 0) ::close(fd_);
    if (archive_fd_ >= 0) ::close(archive_fd_);
}

void ArchiveLock::release() {
    const int rank = mpi::rank(comm_);
    if (rank != 0 && fd_ >= 0) ::close(std::exchange(fd_, -1));
    mpi::check(MPI_Barrier(comm_), "MPI_Barrier");
    // Every other rank has let go; this one still holds it while the file goes, so no new run
    // can lock the old file in between.
    if (rank == 0 && archive_fd_ >= 0) ::close(std::exchange(archive_fd_, -1));
    if (rank == 0 && fd_ >= 0) {
        ::unlink(path_.c_str());
        ::close(std::exchange(fd_, -1));
    }
}

}  // namespace jamsim
