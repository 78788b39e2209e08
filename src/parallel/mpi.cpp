#include "jamsim/parallel/mpi.hpp"

#include <cstdlib>
#include <string>

namespace jamsim::mpi {

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(rc, text, &length);
    throw Error(std::string("MPI: ") + what + " failed: " + std::string(text, length));
}

namespace {
/// True when no launcher (mpirun, srun, a PMI/PMIx server) started this process: MPI_Init
/// then makes it a singleton, a world of one rank.
bool started_without_launcher() {
    for (const char* launcher_variable :
         {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"})
        if (std::getenv(launcher_variable)) return false;
    return true;
}
}  // namespace

Session::Session(int& argc, char**& argv) {
    int initialised = 0;
    check(MPI_Initialized(&initialised), "MPI_Initialized");
    // A singleton (jamsim started without mpirun) needs neither Open MPI's daemon nor its
    // network transports: without them a one-rank `jamsim run` of a tiny campaign takes 0.19 s
    // instead of 0.59 s (tests/README.md, "The quick set and the rest"). The user's own
    // settings of these variables win (setenv does not overwrite); other MPIs ignore them.
    if (!initialised && started_without_launcher()) {
        setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
        setenv("OMPI_MCA_mtl", "^psm,psm2,ofi", 0);
        // Isolated singletons share one session folder (/tmp/ompi.HOST.UID/jf.0/1), which the
        // first to finish removes: the shared-file-pointer component `sm` keeps its mmap file
        // there, so another singleton's MPI_File_open of its archive failed then (2 of 40
        // `jamsim run`s, 8 at a time). jamsim uses no shared file pointer.
        setenv("OMPI_MCA_sharedfp", "^sm", 0);
        // ... and orte_init itself failed once so ("A call to mkdir was unable to create the
        // desired directory: /tmp/ompi.vm.0/jf.0/1", a CI run of the quick set): each singleton
        // gets a session folder of its own, removed when it ends.
        // A folder left by a killed singleton is removed by the next one (SessionFolder).
        if (!std::getenv("OMPI_MCA_orte_tmpdir_base")) {
            session_folder_ = std::make_unique<SessionFolder>();
            if (!session_folder_->path().empty())
                setenv("OMPI_MCA_orte_tmpdir_base", session_folder_->path().c_str(), 1);
        }
    }
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
