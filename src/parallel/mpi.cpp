#include "jamsim/parallel/mpi.hpp"

namespace jamsim::mpi {

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(rc, text, &length);
    throw Error(std::string("MPI: ") + what + " failed: " + std::string(text, length));
}

Session::Session(int& argc, char**& argv) {
    int initialised = 0;
    check(MPI_Initialized(&initialised), "MPI_Initialized");
    // Only the main thread calls MPI; kernel loops run on OpenMP threads between calls.
    int provided = MPI_THREAD_SINGLE;
    if (!initialised) check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    check(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
}

Session::~Session() {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (!finalised) MPI_Finalize();
}

int rank(MPI_Comm comm) {
    int r = 0;
    check(MPI_Comm_rank(comm, &r), "MPI_Comm_rank");
    return r;
}

int size(MPI_Comm comm) {
    int s = 0;
    check(MPI_Comm_size(comm, &s), "MPI_Comm_size");
    return s;
}

int ranks_on_node(MPI_Comm comm) {
    MPI_Comm node = MPI_COMM_NULL;
    check(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
    const int n = size(node);
    check(MPI_Comm_free(&node), "MPI_Comm_free");
    return n;
}

void broadcast(std::string& text, int root, MPI_Comm comm) {
    unsigned long long length = text.size();
    check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, root, comm), "MPI_Bcast (length)");
    text.resize(length);
    if (length > 0) check(MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, root, comm), "MPI_Bcast (text)");
}

void broadcast(int& value, int root, MPI_Comm comm) {
    check(MPI_Bcast(&value, 1, MPI_INT, root, comm), "MPI_Bcast (int)");
}

}  // namespace jamsim::mpi
