// Creation of a campaign archive at the papers' scale: the time Archive::create takes and the
// file it leaves (apparent size and the bytes the filesystem allocated), for a campaign file.
//   jamsim_bench_archive CAMPAIGN.toml OUT.h5 [MAX_REPLICAS]
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/capacity.hpp"
#include "jamsim/parallel/mpi.hpp"

int main(int argc, char** argv) {
    using namespace jamsim;
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s CAMPAIGN.toml OUT.h5 [MAX_REPLICAS]\n", argv[0]);
        return 2;
    }
    mpi::Session session(argc, argv);
    const std::int64_t cap = argc > 3 ? std::atoll(argv[3]) : kDefaultMaxReplicas;
    const auto t0 = std::chrono::steady_clock::now();
    const CampaignSpec spec = load_campaign(argv[1], cap);
    const auto t1 = std::chrono::steady_clock::now();
    Archive archive = Archive::create(MPI_COMM_WORLD, argv[2], spec);
    archive.close();
    const auto t2 = std::chrono::steady_clock::now();
    struct stat s {};
    if (::stat(argv[2], &s) != 0) return 1;
    const ArchiveLayout layout = archive_layout(spec);
    std::printf("%zu replicas x %llu samples: spec read in %.2f s, archive created in %.2f s; file %s "
                "apparent (%s when every replica is written), %s allocated\n",
                spec.replicas.size(), static_cast<unsigned long long>(layout.samples),
                std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(),
                show_bytes(static_cast<double>(s.st_size)).c_str(), show_bytes(layout.bytes).c_str(),
                show_bytes(static_cast<double>(s.st_blocks) * 512.0).c_str());
    return 0;
}
