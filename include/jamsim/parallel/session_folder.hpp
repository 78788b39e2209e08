#pragma once
#include <string>

namespace jamsim::mpi {

/// A singleton's Open MPI session folder (`jamsim-mpi.XXXXXX` under TMPDIR or /tmp), made with
/// mkdtemp and removed when this object ends. Its owner holds an flock on `owner.lock` inside
/// it for its whole life, so that a folder left by a killed jamsim (SIGKILL, an out-of-memory
/// kill, a node's time limit) can be told from a live one's: each new folder's maker removes
/// the folders of this user whose lock it can take. The lock, not a process id, decides:
/// it holds across PID namespaces and, where flock reaches the server, across nodes.
class SessionFolder {
  public:
    /// Sweeps the dead ones and makes a new folder; path() is empty when mkdtemp failed
    /// (Open MPI then uses its own default).
    SessionFolder();
    ~SessionFolder();
    SessionFolder(const SessionFolder&) = delete;
    SessionFolder& operator=(const SessionFolder&) = delete;

    const std::string& path() const { return path_; }

  private:
    std::string path_;
    int lock_descriptor_ = -1;  ///< open (and flocked) while this process lives
};

}  // namespace jamsim::mpi
