#include "jamsim/io/archive_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "jamsim/io/archive.hpp"
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
           "may take a few seconds to exit), or stop it (scancel, kill); the lock is '" + path + "'";
}

std::string host_name() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "unknown host";
    return name;
}

} // namespace

std::string lock_path(const std::string& archive_path) { return archive_path + ".lock"; }

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
        } else if (const int e = set_lock(fd, F_WRLCK); busy(e)) {
            error = busy_message(archive_path, path, fd);
        } else if (unsupported(e)) {
            supported = 0;
            std::fprintf(stderr, "jamsim: warning: the filesystem of '%s' has no file locks (%s): jamsim "
                                 "cannot refuse a second run on this archive; make sure there is none\n",
                         path.c_str(), std::strerror(e));
        } else if (e != 0) {
            error = "cannot lock '" + path + "': " + std::strerror(e);
        } else {
            char started[64];
            std::snprintf(started, sizeof started, "%s", utc_now().c_str());
            const std::string holder = command + " (PID " + std::to_string(::getpid()) + " on " + host_name() +
                                       ", " + std::to_string(mpi::size(comm)) + " ranks, started " + started + ")\n";
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
        throw ArchiveBusy(failed ? "rank " + std::to_string(rank) + " cannot share the lock '" + path + "': " + std::strerror(e)
                                 : "another rank cannot share the lock '" + path + "'");
    }
    return ArchiveLock(comm, path, fd);
}

void ArchiveLock::check_free(const std::string& archive_path) {
    const std::string path = lock_path(archive_path);
    const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) return;  // never locked
    const int e = set_lock(fd, F_WRLCK);
    std::string message = busy(e) ? busy_message(archive_path, path, fd) : "";
    ::close(fd);  // releases what this process holds on it
    if (!message.empty()) throw ArchiveBusy(message);
}

ArchiveLock::ArchiveLock(ArchiveLock&& other) noexcept
    : comm_(other.comm_), path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

ArchiveLock::~ArchiveLock() {
    if (fd_ >= 0) ::close(fd_);
}

void ArchiveLock::release() {
    const int rank = mpi::rank(comm_);
    if (rank != 0 && fd_ >= 0) ::close(std::exchange(fd_, -1));
    mpi::check(MPI_Barrier(comm_), "MPI_Barrier");
    // Every other rank has let go; this one still holds it while the file goes, so no new run
    // can lock the old file in between.
    if (rank == 0 && fd_ >= 0) {
        ::unlink(path_.c_str());
        ::close(std::exchange(fd_, -1));
    }
}

} // namespace jamsim
