// The run loop (fdem run) against a fake simulation: outputs at the scene's
// cadence from t = 0 to the end, a signal stops it after the current step
// with exit 130 and every output written, checkpoints at their cadence.
#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/run_command.hpp"
#include "core/error.hpp"
#include "io/tests/scratch_files.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

// Ballistic particles and an optional static fluid on a tiny mesh.
class FakeTarget final : public RunTarget {
 public:
  FakeTarget(double step_s, double end_s, bool with_mesh, long raise_signal_at = -1)
      : step_s_(step_s), end_s_(end_s), raise_at_(raise_signal_at) {
    particles_.x = {0.5, 0.25};
    particles_.y = {0.5, 0.75};
    particles_.z = {0.9, 0.8};
    particles_.vx = {0.0, 0.0};
    particles_.vy = {0.0, 0.0};
    particles_.vz = {0.0, -0.1};
    particles_.fx = particles_.fy = particles_.fz = {0.0, 0.0};
    particles_.diameter = {0.01, 0.02};
    particles_.mass = {1e-3, 2e-3};
    if (with_mesh) {
      mesh_ = std::make_unique<BoxMesh>(Vec3(0, 0, 0), Vec3(1, 1, 1), std::array<int, 3>{2, 2, 2});
      const auto nodes = static_cast<std::size_t>(mesh_->num_nodes());
      velocity_.assign(3 * nodes, 0.01);
      pressure_.assign(nodes, 5.0);
      source_.assign(3 * nodes, 0.0);
      porosity_.assign(static_cast<std::size_t>(mesh_->num_elements()), 0.9);
    }
  }
  void step() override {
    if (steps_ == fail_at_) throw SolverError("fake blow-up");
    ++steps_;
    for (std::size_t i = 0; i < particles_.size(); ++i) particles_.z[i] += step_s_ * particles_.vz[i];
    if (steps_ == raise_at_) std::raise(SIGINT);  // arrives mid-step, as from a user
  }
  double time() const override { return static_cast<double>(steps_) * step_s_; }
  double step_size() const override { return step_s_; }
  long step_index() const override { return steps_; }
  bool finished() const override { return time() >= end_s_ - 0.5 * step_s_; }
  const Particles& particles() const override { return particles_; }
  const BoxMesh* mesh() const override { return mesh_.get(); }
  std::span<const double> fluid_velocity() const override { return velocity_; }
  std::span<const double> fluid_pressure() const override { return pressure_; }
  std::span<const double> porosity() const override { return porosity_; }
  std::span<const double> source_term() const override { return source_; }
  std::vector<std::pair<std::string, double>> diagnostics() const override {
    return {{"fake_steps", static_cast<double>(steps_)}};
  }
  // Fixed, tiny phase times so the summary's sums are known and "other" stays positive.
  PhaseSeconds step_seconds() const override { return {1e-6, 2e-6, 5e-7, 3e-7}; }
  void save_checkpoint(std::ostream& out) const override { out << "checkpoint at step " << steps_; }
  long fail_at_ = -1;  // step() throws SolverError when this many steps are done

 private:
  double step_s_, end_s_;
  long raise_at_;
  long steps_ = 0;
  Particles particles_;
  std::unique_ptr<BoxMesh> mesh_;
  std::vector<double> velocity_, pressure_, source_, porosity_;
};

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

Scene scene_with(double vtu_s, double csv_s, double checkpoint_s, const fs::path& dir) {
  Scene s;
  s.source_file = "fake.yaml";
  s.time.end_time = 1.0;
  s.output.directory = dir.string();
  s.output.vtu_interval = vtu_s;
  s.output.csv_interval = csv_s;
  s.output.checkpoint_interval = checkpoint_s;
  return s;
}

TEST(RunLoop, VtuAtTheFirstStepReachingEachMultipleOfTheInterval) {
  const fs::path dir = fresh_test_directory("test_run_loop", "cadence", false);
  FakeTarget target(0.1, 1.0, false);
  ASSERT_EQ(run_loop(target, scene_with(0.25, 0.0, 0.0, dir), {}, nullptr), 0);
  const std::string pvd = file_contents(dir / "particles.pvd");
  // t = 0, then the first steps at or past 0.25, 0.5, 0.75, 1.0: 0.3, 0.5, 0.8, 1.0.
  EXPECT_EQ(count_of(pvd, "<DataSet"), 5u);
  for (const char* t : {"\"0\"", "\"0.30000000000000004\"", "\"0.5\"", "\"0.8\"", "\"1\""}) {
    EXPECT_NE(pvd.find(std::string("timestep=") + t), std::string::npos) << t << "\n" << pvd;
  }
  EXPECT_FALSE(fs::exists(dir / "fluid.pvd"));  // no mesh, no fluid output
  fs::remove_all(dir);
}

TEST(RunLoop, CsvEveryStepByDefaultWithProbeAndDiagnosticColumns) {
  const fs::path dir = fresh_test_directory("test_run_loop", "csv", false);
  FakeTarget target(0.1, 1.0, false);
  ASSERT_EQ(run_loop(target, scene_with(0.0, 0.0, 0.0, dir), {}, nullptr), 0);
  const std::string csv = file_contents(dir / "probes.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "time,step,count,mean_x,mean_y,mean_z,mean_vx,mean_vy,mean_vz,max_speed,kinetic_energy,min_z,max_z,"
            "fake_steps");
  EXPECT_EQ(count_of(csv, "\n"), 12u);  // header + t = 0 .. 1 in 11 steps, no duplicate final row
  EXPECT_FALSE(fs::exists(dir / "particles.pvd"));  // vtu_interval 0: no VTU
  fs::remove_all(dir);
}

TEST(RunLoop, MeshFieldsGoToTheFluidSeries) {
  const fs::path dir = fresh_test_directory("test_run_loop", "mesh", false);
  FakeTarget target(0.5, 1.0, true);
  ASSERT_EQ(run_loop(target, scene_with(0.5, 0.0, 0.0, dir), {}, nullptr), 0);
  EXPECT_EQ(count_of(file_contents(dir / "fluid.pvd"), "<DataSet"), 3u);
  const std::string vtu = file_contents(dir / "fluid_000002.vtu");
  EXPECT_NE(vtu.find("NumberOfPoints=\"27\" NumberOfCells=\"40\""), std::string::npos);
  for (const char* name : {"\"velocity\"", "\"pressure\"", "\"source_term\"", "\"porosity\""}) {
    EXPECT_NE(vtu.find(std::string("Name=") + name), std::string::npos) << name;
  }
  fs::remove_all(dir);
}

TEST(RunLoop, VtuIsCompressedBinaryUnlessTheSceneAsksForAscii) {
  for (const VtuFormat format : {VtuFormat::binary, VtuFormat::ascii}) {
    const fs::path dir = fresh_test_directory("test_run_loop", "vtu_format", false);
    FakeTarget target(0.5, 1.0, true);
    Scene scene = scene_with(0.5, 0.0, 0.0, dir);
    scene.output.vtu_format = format;
    ASSERT_EQ(run_loop(target, scene, {}, nullptr), 0);
    const bool binary = format == VtuFormat::binary;
    for (const char* file : {"particles_000002.vtu", "fluid_000002.vtu"}) {
      const std::string vtu = file_contents(dir / file);
      EXPECT_EQ(vtu.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos, binary) << file;
      EXPECT_EQ(vtu.find("<AppendedData encoding=\"raw\">") != std::string::npos, binary) << file;
      // TimeValue is ASCII in both; every other array follows the format.
      EXPECT_EQ(count_of(vtu, "format=\"ascii\""), binary ? 1u : count_of(vtu, "<DataArray")) << file;
    }
    fs::remove_all(dir);
  }
}

TEST(RunLoop, LogNamesThePhysicsAtTheStartAndWhereTheTimeWentAtTheEnd) {
  const fs::path dir = fresh_test_directory("test_run_loop", "log", false);
  FakeTarget target(0.1, 1.0, false);
  Scene scene = scene_with(0.0, 0.0, 0.0, dir);
  scene.effects.fluid = false;
  scene.effects.coupling = CouplingMode::off;
  std::FILE* log = std::tmpfile();
  RunOptions options;
  options.quiet = true;
  ASSERT_EQ(run_loop(target, scene, options, log), 0);
  std::rewind(log);
  std::string text(1 << 14, '\0');
  text.resize(std::fread(text.data(), 1, text.size(), log));
  std::fclose(log);
  EXPECT_NE(text.find("\n  effects   gravity, normal contact (linear spring-dashpot, Eq. 6), walls\n  fluid     none (dry DEM)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("drag ergun"), std::string::npos) << text;  // dry: no drag law
  // 10 steps of the fake's phase times.
  EXPECT_NE(text.find(": fluid 1e-05 s, DEM 2e-05 s (drag 5e-06 s of it), coupling 3e-06 s, output "),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("other -"), std::string::npos) << text;
  fs::remove_all(dir);
}

TEST(RunLoop, SignalFinishesTheStepWritesEverythingAndReturns130) {
  const fs::path dir = fresh_test_directory("test_run_loop", "signal", false);
  FakeTarget target(0.01, 1.0, false, /*raise_signal_at=*/7);
  EXPECT_EQ(run_loop(target, scene_with(0.25, 0.0, 0.5, dir), {}, nullptr), kExitInterrupted);
  EXPECT_EQ(target.step_index(), 7);  // stopped after the step that was running
  const std::string pvd = file_contents(dir / "particles.pvd");
  EXPECT_EQ(count_of(pvd, "<DataSet"), 2u);  // t = 0 and the stop step, written on the way out
  EXPECT_NE(pvd.find("timestep=\"0.07\""), std::string::npos) << pvd;
  const std::string csv = file_contents(dir / "probes.csv");
  EXPECT_EQ(count_of(csv, "\n"), 9u);  // header + steps 0..7
  EXPECT_EQ(file_contents(dir / "checkpoint.bin"), "checkpoint at step 7");
  // The handlers are gone after the loop: a later run starts unflagged.
  FakeTarget again(0.5, 1.0, false);
  EXPECT_EQ(run_loop(again, scene_with(0.0, 0.0, 0.0, fresh_test_directory("test_run_loop", "signal_again", false)), {}, nullptr), 0);
  fs::remove_all(dir);
  fs::remove_all(fresh_test_directory("test_run_loop", "signal_again", false));
}

TEST(RunLoop, SolverFailureKeepsTheOutputOfEveryGoodStep) {
  const fs::path dir = fresh_test_directory("test_run_loop", "failure", false);
  FakeTarget target(0.1, 1.0, false);
  target.fail_at_ = 4;
  EXPECT_THROW(run_loop(target, scene_with(0.25, 0.0, 0.0, dir), {}, nullptr), SolverError);
  // Probe rows of steps 0..4 are on disk, though the CSV is normally rewritten only every 10 s.
  EXPECT_EQ(count_of(file_contents(dir / "probes.csv"), "\n"), 6u);
  EXPECT_EQ(count_of(file_contents(dir / "particles.pvd"), "<DataSet"), 2u);  // t = 0 and 0.3
  fs::remove_all(dir);
}

TEST(RunLoop, CheckpointAtItsCadenceIncludingTheStart) {
  const fs::path dir = fresh_test_directory("test_run_loop", "checkpoint", false);
  FakeTarget target(0.1, 1.0, false);
  ASSERT_EQ(run_loop(target, scene_with(0.0, 0.0, 0.5, dir), {}, nullptr), 0);
  EXPECT_EQ(file_contents(dir / "checkpoint.bin"), "checkpoint at step 10");
  fs::remove_all(dir);
}

TEST(RunLoop, OutputOptionOverridesTheSceneDirectory) {
  const fs::path dir = fresh_test_directory("test_run_loop", "override", false);
  FakeTarget target(0.5, 1.0, false);
  RunOptions options;
  options.output_dir = (dir / "elsewhere").string();
  ASSERT_EQ(run_loop(target, scene_with(0.0, 0.0, 0.0, dir / "scene_dir"), options, nullptr), 0);
  EXPECT_TRUE(fs::exists(dir / "elsewhere" / "probes.csv"));
  EXPECT_FALSE(fs::exists(dir / "scene_dir"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fdem
