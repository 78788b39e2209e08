#pragma once
#include <mpi.h>

#include "jamsim/parallel/session_folder.hpp"

#include <memory>
#include <stdexcept>
#include <string>

namespace jamsim::mpi {

/// Thrown for every failed MPI call (errors return, they do not abort: see Session).
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Check an MPI return code.
void check(int rc, const char* what);

/// MPI_Init / MPI_Finalize as a scope. Sets MPI_ERRORS_RETURN on MPI_COMM_WORLD so that
/// every call's error code reaches check().
class Session {
  public:
    Session(int& argc, char**& argv);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

  private:
    /// A singleton's Open MPI session folder; removed after MPI_Finalize (members outlive the
    /// destructor's body).
    std::unique_ptr<SessionFolder> session_folder_;
};

int rank(MPI_Comm comm);
int size(MPI_Comm comm);
/// Collective: how many ranks of `comm` share this rank's node (its memory).
int ranks_on_node(MPI_Comm comm);

/// Broadcast a string from root (its length first).
void broadcast(std::string& text, int root, MPI_Comm comm);
void broadcast(int& value, int root, MPI_Comm comm);

}  // namespace jamsim::mpi
