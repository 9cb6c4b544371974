// An output folder is owned by one run: a second live run is refused, a
// stale lock is taken over, a folder of another scene is refused unless
// --overwrite (which clears it first), the folder of the scene's inputs is
// refused, a file posing as the folder is bad input (exit 2) before set-up,
// and the run leaves a manifest naming scene, scene hash, start and commit.
#include <gtest/gtest.h>

#include <string>

#include "run_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::FdemProcess;
namespace fs = std::filesystem;

using hard::run_fdem;

TEST(OutputFolder, SecondLiveRunIntoTheFolderIsRefusedNamingTheHolderAndTheFirstRunsSeriesStaysItsOwn) {
  const fs::path dir = hard::scratch_dir("folder_live_lock");
  hard::write_text(dir / "long.yaml", hard::dry_drop_yaml(100.0, ", vtu_interval: 1.0e-4"));
  const fs::path out = dir / "out";
  FdemProcess first({"run", (dir / "long.yaml").string(), "-o", out.string(), "-q", "-t", "1"}, dir);
  ASSERT_TRUE(hard::wait_for([&] { return fs::exists(out / "particles_000002.vtu") || !first.running(); }, 60.0));
  ASSERT_TRUE(first.running()) << first.stderr_text();
  hard::write_text(dir / "short.yaml", hard::dry_drop_yaml(0.001, "", "another drop"));
  fs::create_directories(dir / "second");
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "short.yaml").string(), "-o", out.string(), "-q"}, dir / "second", &err), 2);
  EXPECT_NE(err.find("in use by another fdem run"), std::string::npos) << err;
  EXPECT_NE(err.find("--output"), std::string::npos) << err;
  EXPECT_TRUE(first.running()) << "the first run goes on";
  first.signal(SIGINT);
  EXPECT_EQ(first.wait(), 130) << first.stderr_text();
  // Nothing of the refused run in the folder: the manifest is the first run's.
  const std::string manifest = hard::read_text(out / "run_manifest.json");
  EXPECT_NE(manifest.find("long.yaml"), std::string::npos) << manifest;
  for (const char* key : {"\"scene_hash\": \"", "\"started_utc\": \"20", "\"commit\": \"", "\"scene\": \""})
    EXPECT_NE(manifest.find(key), std::string::npos) << key << " in " << manifest;
}

TEST(OutputFolder, StaleLockOfADeadRunIsReportedAndTakenOver) {
  const fs::path dir = hard::scratch_dir("folder_stale_lock");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(0.002));
  fs::create_directories(dir / "out");
  // What a run killed with -9 leaves: a lock file naming it, held by nobody.
  hard::write_text(dir / "out" / ".fdem.lock", "process 999999999, started 2020-01-01T00:00:00Z");
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q"}, dir, &err), 0)
      << err;
  EXPECT_NE(err.find("stale lock"), std::string::npos) << err;
  EXPECT_NE(err.find("999999999"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(dir / "out" / "probes.csv"));
}

TEST(OutputFolder, FolderOfAnotherSceneIsRefusedAndOverwriteClearsItFirst) {
  const fs::path dir = hard::scratch_dir("folder_other_scene");
  const fs::path out = dir / "out";
  // Scene A writes 6 snapshots and a checkpoint; scene B writes 2 and none.
  hard::write_text(dir / "a.yaml", hard::dry_drop_yaml(0.005, ", vtu_interval: 0.001, checkpoint_interval: 0.005"));
  hard::write_text(dir / "b.yaml", hard::dry_drop_yaml(0.001, ", vtu_interval: 0.001", "drop b"));
  std::string err;
  ASSERT_EQ(run_fdem({"run", (dir / "a.yaml").string(), "-o", out.string(), "-q"}, dir, &err), 0) << err;
  ASSERT_TRUE(fs::exists(out / "particles_000005.vtu"));
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin"));
  EXPECT_EQ(run_fdem({"run", (dir / "b.yaml").string(), "-o", out.string(), "-q"}, dir, &err), 2);
  EXPECT_NE(err.find("another scene"), std::string::npos) << err;
  EXPECT_NE(err.find("a.yaml"), std::string::npos) << "names the scene that owns the folder: " << err;
  EXPECT_NE(err.find("--overwrite"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(out / "particles_000005.vtu")) << "a refusal touches nothing";

  ASSERT_EQ(run_fdem({"run", (dir / "b.yaml").string(), "-o", out.string(), "-q", "--overwrite"}, dir, &err), 0)
      << err;
  EXPECT_FALSE(fs::exists(out / "particles_000005.vtu")) << "scene A's snapshots were cleared";
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin")) << "scene A's checkpoint was cleared";
  EXPECT_EQ(hard::pvd_datasets(out / "particles.pvd").size(), 2u);
  EXPECT_NE(hard::read_text(out / "run_manifest.json").find("b.yaml"), std::string::npos);

  // The same scene again: its earlier output is replaced without asking.
  EXPECT_EQ(run_fdem({"run", (dir / "b.yaml").string(), "-o", out.string(), "-q"}, dir, &err), 0) << err;
  // Files fdem did not write are never taken for an old run.
  const fs::path foreign = dir / "foreign";
  fs::create_directories(foreign);
  hard::write_text(foreign / "notes.txt", "mine");
  EXPECT_EQ(run_fdem({"run", (dir / "b.yaml").string(), "-o", foreign.string(), "-q"}, dir, &err), 2);
  EXPECT_NE(err.find("notes.txt"), std::string::npos) << err;
  EXPECT_EQ(hard::read_text(foreign / "notes.txt"), "mine");
}

TEST(OutputFolder, FolderHoldingTheScenesInputsIsRefusedAndTheInputSurvives) {
  // The case that lost a user's input: particles read from a CSV named
  // probes.csv, output.directory the scene's own folder.
  const fs::path dir = hard::scratch_dir("folder_inputs");
  const std::string particles = "id,d,rho,x,y,z\n0,1e-3,2500,0.005,0.005,0.005\n1,1e-3,2500,0.005,0.005,0.007\n";
  hard::write_text(dir / "probes.csv", particles);
  hard::write_text(dir / "scene.yaml",
                   "effects: {fluid: false, gravity: true, normal_contact: true, walls: true}\n"
                   "domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01]}\n"
                   "particles:\n  - {name: read, placement: csv, file: probes.csv}\n"
                   "contact: {kn: 100, restitution: 0.5}\n"
                   "time: {dem_step: 1.0e-5, end: 0.001}\n"
                   "output: {directory: " + dir.string() + "}\n");
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-q"}, dir, &err), 2);
  EXPECT_NE(err.find("output.directory"), std::string::npos) << err;
  EXPECT_NE(err.find("holds the scene's input"), std::string::npos) << err;
  EXPECT_EQ(hard::read_text(dir / "probes.csv"), particles) << "the input is untouched";
  // --overwrite does not lift it.
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-q", "--overwrite"}, dir, &err), 2);
  EXPECT_EQ(hard::read_text(dir / "probes.csv"), particles);
}

TEST(OutputFolder, OutputPathThatIsAFileIsBadInputBeforeSetUp) {
  const fs::path dir = hard::scratch_dir("folder_is_file");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(0.001));
  hard::write_text(dir / "taken", "a file");
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "taken").string(), "-q"}, dir, &err), 2);
  EXPECT_NE(err.find("is a file, not a folder"), std::string::npos) << err;
  EXPECT_EQ(err.find("fdem run:"), std::string::npos) << "refused before the run's start line: " << err;
  // A missing parent is created, and said so.
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "new" / "deeper").string(), "-q"}, dir, &err),
            0);
  EXPECT_NE(err.find("created the output folder"), std::string::npos) << err;
}

}  // namespace
}  // namespace fdem
