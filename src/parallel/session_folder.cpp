#include "jamsim/parallel/session_folder.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <string>
#include <system_error>

namespace jamsim::mpi {

namespace {

constexpr const char* kPrefix = "jamsim-mpi.";
constexpr const char* kLockName = "/owner.lock";
constexpr const char* kUnlockedName = "/owner.new";  ///< the lock file before it is locked
/// A folder without either lock file is one that another jamsim has just made (mkdtemp, then
/// the lock): only one older than this is taken for a leftover of a process killed in between.
constexpr std::time_t kUnlockedGraceSeconds = 600;

std::string temporary_base() {
    const char* tmp = std::getenv("TMPDIR");
    return tmp && *tmp ? tmp : "/tmp";
}

/// True when `folder` is a session folder whose owner is gone: its lock can be taken (the
/// kernel drops an flock when its holder dies), or it never got one and is old.
bool owner_is_gone(const std::string& folder, const struct stat& folder_status) {
    const int descriptor = ::open((folder + kLockName).c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
    if (descriptor < 0) {
        // No lock: a folder being made (young), or one whose filesystem refused the lock
        // (its `owner.new` stays then: kept, since its owner cannot be told from a dead one).
        if (errno != ENOENT) return false;
        struct stat unlocked {};
        return ::stat((folder + kUnlockedName).c_str(), &unlocked) != 0 &&
               std::time(nullptr) - folder_status.st_mtime > kUnlockedGraceSeconds;
    }
    const bool gone = ::flock(descriptor, LOCK_EX | LOCK_NB) == 0;
    ::close(descriptor);  // drops the lock again: the removal below needs none
    return gone;
}

/// Removes this user's session folders under `base` whose owners are gone. Best effort:
/// nothing here may stop a command from starting.
void remove_dead_folders(const std::string& base) {
    DIR* listing = ::opendir(base.c_str());
    if (!listing) return;
    const std::size_t prefix_length = std::strlen(kPrefix);
    while (const dirent* entry = ::readdir(listing)) {
        const std::string name = entry->d_name;
        if (name.size() != prefix_length + 6 || name.compare(0, prefix_length, kPrefix) != 0) continue;
        const std::string folder = base + "/" + name;
        struct stat folder_status {};
        if (::lstat(folder.c_str(), &folder_status) != 0 || !S_ISDIR(folder_status.st_mode) ||
            folder_status.st_uid != ::getuid())
            continue;
        if (!owner_is_gone(folder, folder_status)) continue;
        std::error_code ignored;
        std::filesystem::remove_all(folder, ignored);
    }
    ::closedir(listing);
}

}  // namespace

SessionFolder::SessionFolder() {
    const std::string base = temporary_base();
    remove_dead_folders(base);
    std::string name = base + "/" + kPrefix + "XXXXXX";
    if (!::mkdtemp(name.data())) return;
    path_ = name;
    // The lock is taken under another name and then renamed into place, so that a sweeper
    // never finds an `owner.lock` that is not yet locked.
    const std::string unlocked = name + kUnlockedName;
    lock_descriptor_ = ::open(unlocked.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (lock_descriptor_ >= 0 && ::flock(lock_descriptor_, LOCK_EX | LOCK_NB) == 0)
        ::rename(unlocked.c_str(), (name + kLockName).c_str());
}

SessionFolder::~SessionFolder() {
    if (path_.empty()) return;
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
    if (lock_descriptor_ >= 0) ::close(lock_descriptor_);
}

}  // namespace jamsim::mpi
