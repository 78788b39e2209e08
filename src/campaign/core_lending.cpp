#include "jamsim/campaign/core_lending.hpp"

#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "jamsim/parallel/mpi.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

std::vector<RankCores> gather_rank_cores(MPI_Comm comm) {
    MPI_Comm node = MPI_COMM_NULL;
    mpi::check(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
    int leader = mpi::rank(comm);  // the node's lowest rank names it
    const int rc = MPI_Allreduce(MPI_IN_PLACE, &leader, 1, MPI_INT, MPI_MIN, node);
    mpi::check(MPI_Comm_free(&node), "MPI_Comm_free");
    mpi::check(rc, "MPI_Allreduce (node leader)");
    int most = kernel_threads();
    cpu_set_t mask;
    if (omp_get_proc_bind() == omp_proc_bind_false && sched_getaffinity(0, sizeof mask, &mask) == 0)
        most = std::max(most, CPU_COUNT(&mask));
    const long long mine[3] = {leader, kernel_threads(), most};
    std::vector<long long> all(3 * static_cast<std::size_t>(mpi::size(comm)));
    mpi::check(MPI_Allgather(mine, 3, MPI_LONG_LONG, all.data(), 3, MPI_LONG_LONG, comm), "MPI_Allgather (cores)");
    std::vector<RankCores> out(static_cast<std::size_t>(mpi::size(comm)));
    for (std::size_t r = 0; r < out.size(); ++r)
        out[r] = {
            .node = all[3 * r], .own = static_cast<int>(all[3 * r + 1]), .most = static_cast<int>(all[3 * r + 2])};
    return out;
}

void park_until(const std::function<bool()>& ready, std::chrono::microseconds longest) {
    for (auto pause = std::chrono::microseconds(50); !ready(); pause = std::min(pause * 2, longest))
        std::this_thread::sleep_for(pause);
}

void park_until_complete(MPI_Request& request, const char* what) {
    park_until(
        [&] {
            int done = 0;
            mpi::check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
            return done != 0;
        },
        std::chrono::microseconds(10000));
}

}  // namespace jamsim
