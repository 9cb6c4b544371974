// The sample scenes in examples/ are accepted by `fdem check` and give the
// paper's counts; `fdem run` on the tiny dry scene writes a PVD/VTU/CSV that
// an independent XML reader loads; SIGINT/SIGTERM stop a run with exit 130
// and complete output up to the last step.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/tests/scratch_files.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

const std::string kExamples = std::string(FDEM_SOURCE_DIR) + "/examples/";
const std::string kStudies = std::string(FDEM_SOURCE_DIR) + "/verification/";

int exit_code_of(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

// vtk_check.py exit status (0: every dataset parses with consistent counts).
int vtk_check(const fs::path& file, const fs::path& dump) {
  const std::string command = std::string(FDEM_PYTHON) + " " + FDEM_SOURCE_DIR + "/solver/io/tests/vtk_check.py " +
                              file.string() + " > " + dump.string();
  return exit_code_of(std::system(command.c_str()));
}

class ExampleScene : public ::testing::TestWithParam<const char*> {};

TEST_P(ExampleScene, FdemCheckAcceptsIt) {
  const std::string path = std::string(FDEM_SOURCE_DIR) + "/" + GetParam();
  const std::string command = std::string(FDEM_EXE) + " check " + path + " > /dev/null";
  EXPECT_EQ(exit_code_of(std::system(command.c_str())), 0) << path;
}

INSTANTIATE_TEST_SUITE_P(Samples, ExampleScene,
                         ::testing::Values("examples/dry_drop.yaml", "verification/settling/settling.yaml",
                                           "verification/channel/channel.yaml", "verification/plume/plume.yaml"),
                         [](const auto& param_info) { return fs::path(param_info.param).stem().string(); });

TEST(ExampleScenes, CountsMatchThePaper) {
  const auto tets = [](const Scene& s) { return 5 * s.cells[0] * s.cells[1] * s.cells[2]; };
  const Scene settling = load_scene(kStudies + "settling/settling.yaml");
  EXPECT_EQ(tets(settling), 12100);  // Sect. 4.1
  const Scene channel = load_scene(kStudies + "channel/channel.yaml");
  EXPECT_EQ(tets(channel), 6000);  // Sect. 4.3
  EXPECT_EQ(generate_particles(channel).size(), 4800u);
  const Scene plume = load_scene(kStudies + "plume/plume.yaml");
  EXPECT_EQ(tets(plume), 12500);  // Sect. 4.4
  EXPECT_EQ(generate_particles(plume).size(), 28224u);
}

TEST(FdemRun, DrySceneWritesAPvdThatReadsBack) {
  const fs::path dir = fresh_test_directory("test_examples", "run");
  const std::string command =
      std::string(FDEM_EXE) + " run " + kExamples + "dry_drop.yaml --quiet --output " + dir.string() + " 2>/dev/null";
  ASSERT_EQ(exit_code_of(std::system(command.c_str())), 0);
  ASSERT_EQ(vtk_check(dir / "particles.pvd", dir / "dump.txt"), 0) << file_contents(dir / "dump.txt");
  const std::string dump = file_contents(dir / "dump.txt");
  // vtu_interval 0.01 s to 0.05 s: t = 0, 0.01, ..., 0.05.
  std::size_t datasets = 0;
  for (std::size_t at = dump.find("dataset "); at != std::string::npos; at = dump.find("dataset ", at + 1)) ++datasets;
  EXPECT_EQ(datasets, 6u);
  EXPECT_NE(dump.find("points 27 cells 27"), std::string::npos);
  EXPECT_NE(dump.find("dataset 0.05 particles_000005.vtu"), std::string::npos);
  // Probes every 0.001 s: t = 0 .. 0.05 is 51 rows after the header.
  const std::string csv = file_contents(dir / "probes.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 52);
  EXPECT_EQ(csv.rfind("time,step,count,", 0), 0u);
  fs::remove_all(dir);
}

// Starts `fdem run` on a long dry scene, sends `signal_number` once output
// exists, and returns the exit code.
int run_and_signal(const fs::path& dir, int signal_number) {
  std::string scene = file_contents(kExamples + "dry_drop.yaml");
  scene.replace(scene.find("end: 0.05"), 9, "end: 1000");
  std::ofstream(dir / "long.yaml") << scene;
  const pid_t child = ::fork();
  if (child == 0) {
    std::freopen("/dev/null", "w", stderr);
    ::execl(FDEM_EXE, FDEM_EXE, "run", (dir / "long.yaml").c_str(), "--quiet", "--output", (dir / "out").c_str(),
            static_cast<char*>(nullptr));
    ::_exit(99);
  }
  // Wait (at most 20 s) until a few outputs exist, then interrupt.
  for (int i = 0; i < 400 && !fs::exists(dir / "out" / "particles_000003.vtu"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(child, signal_number);
  int status = 0;
  ::waitpid(child, &status, 0);
  return exit_code_of(status);
}

TEST(FdemRun, SigintStopsWithExit130AndCompleteOutput) {
  const fs::path dir = fresh_test_directory("test_examples", "sigint");
  EXPECT_EQ(run_and_signal(dir, SIGINT), 130);
  EXPECT_EQ(vtk_check(dir / "out" / "particles.pvd", dir / "dump.txt"), 0) << file_contents(dir / "dump.txt");
  // The stop step's state is written: the last CSV row's time equals the last dataset's time.
  const std::string csv = file_contents(dir / "out" / "probes.csv");
  const std::string last_row = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  const std::string dump = file_contents(dir / "dump.txt");
  const std::size_t last_dataset = dump.rfind("dataset ");
  const std::string dataset_time = dump.substr(last_dataset + 8, dump.find(' ', last_dataset + 8) - last_dataset - 8);
  EXPECT_EQ(last_row.substr(0, last_row.find(',')), dataset_time);
  // No temporary left behind.
  for (const auto& entry : fs::directory_iterator(dir / "out")) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
  fs::remove_all(dir);
}

TEST(FdemRun, SigtermStopsWithExit130) {
  const fs::path dir = fresh_test_directory("test_examples", "sigterm");
  EXPECT_EQ(run_and_signal(dir, SIGTERM), 130);
  EXPECT_EQ(vtk_check(dir / "out" / "particles.pvd", dir / "dump.txt"), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fdem
