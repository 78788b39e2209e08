// The campaign archive written through the MPI-IO driver and read back in C++.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>

#include "jamsim/archive/archive.hpp"
#include "jamsim/spec/campaign_spec.hpp"

using namespace jamsim;

namespace {
const char* kSpec = R"(
[campaign]
name = "archive-test"
output = "unused.h5"
[run]
strain = 0.05
sample_interval = 0.01
[sweep]
N = [64, 128]
phi = [0.8]
rate = [1e-2]
)";
}  // namespace

TEST(Archive, WriteReadBackFailAndImport) {
    const CampaignSpec spec = parse_campaign(kSpec, "inline.toml");
    ASSERT_EQ(spec.replicas.size(), 2u);
    const std::string path = "archive_test.h5", copy = "archive_copy.h5";
    std::filesystem::remove(path);
    std::filesystem::remove(copy);
    auto archive = Archive::create(MPI_COMM_SELF, path, spec);
    for (auto s : archive.read_status()) EXPECT_EQ(s, ReplicaStatus::Pending);
    const ReplicaResult result = run_replica(spec.replicas[1]);
    archive.mark_running(1, 0);
    EXPECT_EQ(archive.read_status()[1], ReplicaStatus::Running);
    archive.write_done(1, result, 0, 2.5);
    archive.write_failed(0, "deliberate failure for the test", 0.5, 0);
    archive.close();
    EXPECT_EQ(Archive::check_existing(path, spec).kind, Archive::Fit::Kind::Same);

    // Read back with the serial driver, independent of the writer's code path.
    h5::quiet_errors();
    {
        const auto file = h5::open_file_readonly(path);
        const auto pressure = h5::read_dataset(file.get(), "/timeseries/pressure");
        const std::size_t width = pressure.size() / 2, rows = result.series.size();
        ASSERT_EQ(rows, static_cast<std::size_t>(sample_count(spec.replicas[1])));
        for (std::size_t k = 0; k < width; ++k) {
            EXPECT_TRUE(std::isnan(pressure[k]));  // replica 0 failed: no rows
            if (k < rows)
                EXPECT_EQ(pressure[width + k], result.series[k].pressure);
            else
                EXPECT_TRUE(std::isnan(pressure[width + k]));
        }
        const auto x = h5::read_dataset(file.get(), "/final/x");
        const auto fin = final_configuration(result.final_state);
        // Layout 4: the disks of all replicas end to end; replica 1 follows replica 0's 64.
        ASSERT_EQ(x.size(), 64u + 128u);
        const auto offset = h5::read_all<std::int64_t>(file.get(), "/replicas/particle_offset", H5T_NATIVE_INT64);
        ASSERT_EQ(offset, (std::vector<std::int64_t>{0, 64}));
        for (std::size_t k = 0; k < fin.x.size(); ++k) EXPECT_EQ(x[64 + k], fin.x[k]);
        // The threads it ended on, for the done replica only (0: not done).
        EXPECT_EQ(h5::read_all<double>(file.get(), "/replicas/threads", H5T_NATIVE_DOUBLE),
                  (std::vector<double>{0, 2.5}));
    }
    const ArchiveSummary s = summarize_archive(path);
    EXPECT_EQ(s.done, 1);
    EXPECT_EQ(s.failed, 1);
    ASSERT_EQ(s.failures.size(), 1u);
    EXPECT_EQ(s.failures[0], "replica 0: deliberate failure for the test");
    const StoredCampaign stored = read_stored_campaign(path);
    EXPECT_EQ(fingerprint(stored.spec), fingerprint(spec));

    // Import into a fresh archive of the same campaign: identical rows.
    auto second = Archive::create(MPI_COMM_SELF, copy, spec);
    second.import_replica(path, 1);
    EXPECT_EQ(second.read_status()[1], ReplicaStatus::Done);
    EXPECT_EQ(second.read_status()[0], ReplicaStatus::Pending);
    second.close();
    {
        const auto a = h5::open_file_readonly(path), b = h5::open_file_readonly(copy);
        const auto pa = h5::read_dataset(a.get(), "/timeseries/shear_stress");
        const auto pb = h5::read_dataset(b.get(), "/timeseries/shear_stress");
        for (std::size_t k = pa.size() / 2; k < pa.size(); ++k)
            EXPECT_TRUE(pa[k] == pb[k] || (std::isnan(pa[k]) && std::isnan(pb[k])));
        EXPECT_EQ(h5::read_all<double>(b.get(), "/replicas/threads", H5T_NATIVE_DOUBLE)[1], 2.5);
    }

    // Another campaign's spec is refused by check_existing.
    std::string other = kSpec;
    other.replace(other.find("0.8"), 3, "0.7");
    const Archive::Fit fit = Archive::check_existing(path, parse_campaign(other, "other.toml"));
    EXPECT_EQ(fit.kind, Archive::Fit::Kind::OtherCampaign);
    const std::string& why = fit.why;
    EXPECT_NE(why.find("different campaign"), std::string::npos) << why;
}

// A stamp writes over attributes made at creation and allocates nothing: the file keeps its
// size. (A variable-length stamp took a new global heap collection at the end of the file;
// when writing it failed on one rank, the file was left shorter than its superblock says and
// HDF5 refused it for good, "run the same command again" included.)
// A failure's reason longer than its 200 bytes is cut at a word's end and marked (it was cut
// mid-word), never inside a UTF-8 character.
TEST(Archive, LongFailureReasonEndsAtAWord) {
    const CampaignSpec spec = parse_campaign(kSpec, "inline.toml");
    const std::string path = "archive_reason.h5";
    std::filesystem::remove(path);
    std::string reason = "KSP did not converge:";
    for (int k = 0; reason.size() < 400; ++k)
        reason += k % 7 == 3 ? " \u03c6\u03c6\u03c6" : " iterations" + std::to_string(k);
    {
        auto archive = Archive::create(MPI_COMM_SELF, path, spec);
        archive.write_failed(0, reason, 0.5, 0);
        archive.close();
    }
    const ArchiveSummary summary = summarize_archive(path);
    ASSERT_EQ(summary.failures.size(), 1u);
    const std::string prefix = "replica 0: ";
    const std::string stored = summary.failures[0].substr(prefix.size());
    ASSERT_GE(stored.size(), 150u);
    EXPECT_LE(stored.size(), 199u);
    ASSERT_TRUE(stored.ends_with(" ...")) << stored;
    const std::string kept = stored.substr(0, stored.size() - 4);
    EXPECT_TRUE(reason.starts_with(kept + " ")) << stored;  // whole words of the reason
    std::filesystem::remove(path);
}

TEST(Archive, StampsAllocateNothing) {
    const CampaignSpec spec = parse_campaign(kSpec, "inline.toml");
    const std::string path = "archive_stamps.h5";
    std::filesystem::remove(path);
    Archive::create(MPI_COMM_SELF, path, spec).close();
    const auto size_at_creation = std::filesystem::file_size(path);
    {
        Archive archive = Archive::open(MPI_COMM_SELF, path);
        for (const char* stamp : {"run_started", "run_finished", "merged", "extended", "grown", "run_finished"})
            archive.stamp(stamp);
        archive.close();
    }
    EXPECT_EQ(std::filesystem::file_size(path), size_at_creation);
    const ArchiveSummary s = summarize_archive(path);
    EXPECT_EQ(s.started.size(), 20u) << s.started;  // 2026-11-29T09:01:35Z
    EXPECT_EQ(s.finished.size(), 20u) << s.finished;
    EXPECT_EQ(s.merged.size(), 20u) << s.merged;
    EXPECT_EQ(s.ranks, 1);

    // An archive made before (a variable-length stamp): the stamp replaces it.
    {
        const h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, "open " + path);
        h5::check(H5Adelete(file.get(), "run_started"), "delete run_started");
        h5::write_attribute(file.get(), "run_started", std::string("2020-01-01T00:00:00Z"));
    }
    {
        Archive archive = Archive::open(MPI_COMM_SELF, path);
        archive.stamp("run_started");
        archive.close();
    }
    const ArchiveSummary again = summarize_archive(path);
    EXPECT_EQ(again.started.size(), 20u) << again.started;
    EXPECT_NE(again.started, "2020-01-01T00:00:00Z");
}

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    const int rc = RUN_ALL_TESTS();
    MPI_Finalize();
    return rc;
}
