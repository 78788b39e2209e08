// The campaign lifecycle's decisions called as a library (campaign/lifecycle.hpp), without the
// command line: what is new, resumed, extended, grown or refused, what a run and a merge did.
// One process (MPI_COMM_SELF); its own main starts MPI.
#include <gtest/gtest.h>
#include <mpi.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "jamsim/archive/archive.hpp"
#include "jamsim/campaign/lifecycle.hpp"

namespace fs = std::filesystem;
using namespace jamsim;

namespace {

/// A fresh folder per test, removed after it.
class Lifecycle : public ::testing::Test {
  protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("jamsim_lifecycle_" + std::string(info->name()) + "_" + std::to_string(static_cast<long>(::getpid())));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    /// A small RD0 campaign file writing `output` (in dir): N = 64, φ = 0.84.
    std::string campaign(const std::string& file, double strain, int seeds, const std::string& output = "a.h5",
                         const std::string& rates = "[3e-3]") const {
        const fs::path path = dir / file;
        std::ofstream(path) << "[campaign]\nname = \"life\"\noutput = \"" << (dir / output).string()
                            << "\"\n[run]\ntransient = 0.02\nstrain = " << strain
                            << "\nsample_interval = 0.02\n[sweep]\nN = [64]\nphi = [0.84]\nrate = " << rates
                            << "\nseeds = " << seeds << "\n";
        return path.string();
    }
    /// An empty archive of the campaign in `file` (every replica pending).
    void create_archive(const std::string& file) const {
        const CampaignSpec spec = load_campaign(file);
        Archive::create(MPI_COMM_SELF, spec.output, spec).close();
    }
    static RunDecision check(const std::string& file, bool dry_run = false) {
        RunRequest request;
        request.spec_path = file;
        request.dry_run = dry_run;
        return check_run(request);
    }
    static RunOutcome run(const std::string& file) {
        const RunDecision d = check(file);
        EXPECT_EQ(d.error, "");
        RunSettings settings;
        settings.spec_path = file;
        return run_campaign(MPI_COMM_SELF, load_campaign(file), d, settings);
    }
};

TEST_F(Lifecycle, NewArchiveIsFreshAndSized) {
    const RunDecision d = check(campaign("c.toml", 0.1, 2));
    EXPECT_EQ(d.error, "");
    EXPECT_EQ(d.mode, OutputMode::Fresh);
    EXPECT_EQ(d.output, (dir / "a.h5").string());
    EXPECT_TRUE(d.sized);
    EXPECT_GT(d.capacity.archive_bytes, 0.0);
    EXPECT_FALSE(fs::exists(dir / "a.h5"));  // checking creates nothing
}

TEST_F(Lifecycle, SameCampaignRunLongerIsExtended) {
    create_archive(campaign("short.toml", 0.1, 2));
    const RunDecision d = check(campaign("long.toml", 0.2, 2));
    EXPECT_EQ(d.error, "");
    EXPECT_EQ(d.mode, OutputMode::Extend);
}

TEST_F(Lifecycle, ShorterRunIsRefusedInWords) {
    create_archive(campaign("long.toml", 0.2, 2));
    const RunDecision d = check(campaign("short.toml", 0.1, 2));
    EXPECT_NE(d.error.find("can be extended to a larger strain"), std::string::npos) << d.error;
    EXPECT_NE(d.error.find("short.toml"), std::string::npos) << d.error;
}

TEST_F(Lifecycle, MoreSeedsGrowTheArchive) {
    create_archive(campaign("two.toml", 0.1, 2));
    const RunDecision d = check(campaign("three.toml", 0.1, 3));
    EXPECT_EQ(d.error, "");
    EXPECT_EQ(d.mode, OutputMode::Grow);
    EXPECT_EQ(d.grow_kept, 2);
    ASSERT_EQ(d.grow_source.size(), 3u);
    EXPECT_EQ(d.grow_source[2], -1);  // the new seed
}

TEST_F(Lifecycle, ADifferentCampaignIsRefused) {
    create_archive(campaign("a.toml", 0.1, 2));
    // The same sweep at another transient: neither an extension nor a growth.
    const fs::path path = dir / "b.toml";
    std::ofstream(path) << "[campaign]\nname = \"life\"\noutput = \"" << (dir / "a.h5").string()
                        << "\"\n[run]\ntransient = 0.04\nstrain = 0.1\nsample_interval = 0.02\n[sweep]\nN = "
                           "[64]\nphi = [0.84]\nrate = [3e-3]\nseeds = 2\n";
    const RunDecision d = check(path.string());
    EXPECT_NE(d.error.find("belongs to a different campaign"), std::string::npos) << d.error;
}

TEST_F(Lifecycle, DryRunMakesNoFolderAndTheRunMakesIt) {
    const std::string file = campaign("c.toml", 0.1, 1, "deep/er/a.h5");
    EXPECT_EQ(check(file, true).error, "");
    EXPECT_FALSE(fs::exists(dir / "deep"));
    EXPECT_EQ(check(file, false).error, "");
    EXPECT_TRUE(fs::is_directory(dir / "deep" / "er"));
}

TEST_F(Lifecycle, UnmakeableFolderIsRefusedAlikeInDryRunAndRun) {
    const fs::path path = dir / "c.toml";
    std::ofstream(path) << "[campaign]\nname = \"life\"\noutput = \"/dev/null/out.h5\"\n[sweep]\nN = [64]\nphi = "
                           "[0.84]\nrate = [3e-3]\nseeds = 1\n";
    const std::string dry = check(path.string(), true).error, real = check(path.string(), false).error;
    EXPECT_NE(dry.find("is not allowed"), std::string::npos) << dry;
    EXPECT_EQ(dry, real);
}

TEST_F(Lifecycle, ARunRunsEveryReplicaOnceAndKeepsThemAfter) {
    const std::string file = campaign("c.toml", 0.04, 2, "a.h5", "[3e-3, 6e-3]");
    const RunOutcome first = run(file);
    EXPECT_EQ(first.end, RunOutcome::End::finished);
    EXPECT_EQ(first.ran, 4);
    EXPECT_EQ(first.failed, 0);
    const RunOutcome again = run(file);  // resumed: everything is done
    EXPECT_EQ(again.end, RunOutcome::End::finished);
    EXPECT_EQ(again.ran, 0);
    EXPECT_EQ(again.skipped, 4);
}

TEST_F(Lifecycle, MergeRefusesTheOutputAsInputAndForeignCampaigns) {
    create_archive(campaign("a.toml", 0.1, 2, "a.h5"));
    EXPECT_THROW(merge_archives((dir / "a.h5").string(), {(dir / "a.h5").string()}), CampaignRefused);
    const fs::path other = dir / "b.toml";
    std::ofstream(other) << "[campaign]\nname = \"life\"\noutput = \"" << (dir / "b.h5").string()
                         << "\"\n[run]\ntransient = 0.04\nstrain = 0.1\nsample_interval = 0.02\n[sweep]\nN = "
                            "[64]\nphi = [0.84]\nrate = [3e-3]\nseeds = 2\n";
    create_archive(other.string());
    try {
        merge_archives((dir / "m.h5").string(), {(dir / "a.h5").string(), (dir / "b.h5").string()});
        FAIL() << "merged archives of different campaigns";
    } catch (const CampaignRefused& e) {
        EXPECT_NE(std::string(e.what()).find("belongs to a different campaign"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "m.h5"));  // nothing written
}

TEST_F(Lifecycle, MergeOfSweepsHoldsTheUnionOfTheirReplicas) {
    const std::string a = campaign("a.toml", 0.04, 1, "a.h5", "[3e-3]");
    const std::string b = campaign("b.toml", 0.04, 1, "b.h5", "[6e-3]");
    EXPECT_EQ(run(a).ran, 1);
    EXPECT_EQ(run(b).ran, 1);
    const MergeOutcome m = merge_archives((dir / "m.h5").string(), {(dir / "a.h5").string(), (dir / "b.h5").string()});
    EXPECT_EQ(m.copied, 2);
    EXPECT_EQ(m.replicas, 2u);
    EXPECT_TRUE(m.union_campaign);
    const MergeOutcome again =
        merge_archives((dir / "m.h5").string(), {(dir / "a.h5").string(), (dir / "b.h5").string()});
    EXPECT_EQ(again.copied, 0);  // completed already
}

}  // namespace

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    MPI_Init(&argc, &argv);
    const int failed = RUN_ALL_TESTS();
    MPI_Finalize();
    return failed;
}
