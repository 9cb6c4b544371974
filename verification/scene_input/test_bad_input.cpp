// Bad scenes are refused before anything runs, with ONE line naming the file,
// the key (dotted path), its line and the value, and `fdem check` exits 2.
// Each file in bad/ starts with a comment saying what is wrong with it.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

struct BadScene {
  const char* name;    // bad/<name>.yaml
  const char* file;    // the file the message names ("" = the scene itself)
  const char* key;
  int line;            // 0 = no line (the key is absent)
  const char* value;
  const char* reason;  // a fragment of the reason
};

void PrintTo(const BadScene& s, std::ostream* os) { *os << s.name; }

const std::string kBadDir = std::string(FDEM_SOURCE_DIR) + "/verification/scene_input/bad/";

// Each row was checked by hand against its file: the line is where the bad
// value (or, for a missing key, its enclosing mapping) is written.
const BadScene kBadScenes[] = {
    {"unknown_key_typo", "", "fluid.viscosty", 6, "1.0e-3", "did you mean 'viscosity'?"},
    {"unknown_top_level_key", "", "partcles", 4, "- name: beads", "did you mean 'particles'?"},
    {"wrong_type_density", "", "particles[0].density", 10, "heavy", "expected a number"},
    {"missing_time", "", "time", 2, "", "required key missing"},
    {"negative_diameter", "", "particles[0].size", 11, "-7.6e-4", "diameter must be > 0"},
    {"zero_viscosity", "", "fluid.viscosity", 6, "0", "viscosity must be > 0"},
    {"unknown_fluid_model", "", "fluid.model", 7, "vans_c", "expected one of: simplified, vans_a, vans_b"},
    {"time_derivative_simplified", "", "fluid.porosity_time_derivative", 7, "true", "volume-averaged models only"},
    {"projection_vans", "", "fluid.scheme", 7, "projection", "simplified model only"},
    {"projection_petsc", "", "fluid.scheme", 7, "projection", "need scheme: monolithic"},
    {"negative_fluid_density", "", "fluid.density", 5, "-1000", "density must be > 0"},
    {"zero_dem_step", "", "time.dem_step", 12, "0", "time step must be > 0"},
    {"end_before_step", "", "time.end", 14, "0.001", "below one time step"},
    {"empty_domain", "", "domain.upper", 3, "[0.01, 0.01, 0.0]", "empty box"},
    {"particle_outside_domain", "", "particles[0].position", 10, "[0.022, 0.022, 0.0801]", "does not lie inside the domain"},
    {"lattice_region_outside", "", "particles[0].region", 7, "{lower: [0.002, 0.002, 0.004], upper: [0.008, 0.008, 0.012]}",
     "outside the domain"},
    {"lattice_overlap", "", "particles[0].lattice", 8, "5", "particles would overlap"},
    {"normal_nonpositive_bound", "", "particles[0].size.min", 9, "0.0", "can draw diameters <= 0"},
    {"normal_without_truncation", "", "particles[0].size.min", 9, "", "lower truncation bound"},
    {"normal_empty_truncation", "", "particles[0].size.min", 9, "1.0e-3", "rejection would stall"},
    {"restitution_out_of_range", "", "contact.restitution", 11, "1.5", "must lie in (0, 1]"},
    {"cn_and_restitution", "", "contact.restitution", 11, "0.5", "not both"},
    {"unknown_contact_law", "", "contact.law", 11, "hertz_mindlin", "expected one of: linear_spring_dashpot"},
    {"subcycles_inconsistent", "", "time.subcycles", 14, "50", "differs from fluid_step"},
    {"steps_not_whole", "", "time.dem_step", 14, "3.0e-3", "not a whole number of subcycles"},
    {"zero_cells", "", "mesh.cells", 3, "0", "must be >= 1"},
    {"cell_size_not_whole", "", "mesh.cell_size", 3, "0.003", "not a whole number of cells"},
    {"coupling_without_fluid", "", "effects.coupling", 2, "two_way", "needs effects.fluid: true"},
    {"unknown_drag_law", "", "effects.drag", 2, "schiller_naumann", "expected one of: ergun_wen_yu, stokes"},
    {"duplicate_key", "", "contact.kn", 11, "200", "appears twice"},
    {"yaml_syntax", "", "(syntax)", 9, "", "not valid YAML"},
    {"vector_wrong_length", "", "particles[0].position", 10, "[0.022, 0.070]", "list of 3 numbers"},
    {"csv_particle_outside", "outside.csv", "x,y,z", 3, "[0.005, 0.0099, 0.005]", "outside the domain"},
};

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

struct CommandResult {
  int exit_code = -1;
  std::string stderr_text;
};

// Runs `fdem check PATH`, keeping stderr only.
CommandResult fdem_check(const std::string& path) {
  const std::string command = std::string(FDEM_EXE) + " check '" + path + "' 2>&1 >/dev/null";
  CommandResult r;
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.stderr_text.append(buffer, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST_P(BadSceneTest, RefusedWithFileKeyLineAndValue) {
  const BadScene& s = GetParam();
  const std::string path = kBadDir + s.name + ".yaml";
  const std::string file = *s.file != '\0' ? kBadDir + s.file : path;
  try {
    (void)load_scene(path);
    FAIL() << path << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.key(), s.key);
    EXPECT_EQ(e.line(), s.line);
    EXPECT_EQ(e.value().substr(0, std::string(s.value).size()), s.value);
    const std::string message = e.what();
    EXPECT_NE(message.find(s.reason), std::string::npos) << message;
    // The one line starts with file:line, then names the key and the value.
    EXPECT_EQ(message.rfind(file + ":" + std::to_string(s.line) + ": key '" + s.key + "'", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

TEST_P(BadSceneTest, FdemCheckExits2WithOneLine) {
  const BadScene& s = GetParam();
  const std::string path = kBadDir + s.name + ".yaml";
  const CommandResult r = fdem_check(path);
  EXPECT_EQ(r.exit_code, 2);
  ASSERT_FALSE(r.stderr_text.empty());
  EXPECT_EQ(r.stderr_text.find('\n'), r.stderr_text.size() - 1) << "more than one line:\n" << r.stderr_text;
  EXPECT_NE(r.stderr_text.find(std::string("key '") + s.key + "'"), std::string::npos) << r.stderr_text;
  EXPECT_NE(r.stderr_text.find(s.reason), std::string::npos) << r.stderr_text;
}

INSTANTIATE_TEST_SUITE_P(Scenes, BadSceneTest, ::testing::ValuesIn(kBadScenes),
                         [](const ::testing::TestParamInfo<BadScene>& param_info) { return std::string(param_info.param.name); });

TEST(BadScene, PaperChannelContactAtItsDemStepIsRefusedWithTheStableBound) {
  // The paper's channel contact (Sect. 4.3, Table 3): Kn 1e5 N/m, Cn 0.026 N s/m, dt 1e-5 s. The scene is well formed
  // (it loads); `fdem check` prints the stability table, then refuses it.
  const std::string path = kBadDir + "paper_channel_unstable_step.yaml";
  EXPECT_NO_THROW((void)load_scene(path));
  const CommandResult r = fdem_check(path);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find("key 'time.dem_step' = '1e-05'"), std::string::npos) << r.stderr_text;
  EXPECT_NE(r.stderr_text.find("exceeds the stable bound"), std::string::npos) << r.stderr_text;
  EXPECT_NE(r.stderr_text.find("allow_unstable_step"), std::string::npos) << r.stderr_text;
}

TEST(BadScene, MissingSceneFileExits2) {
  const CommandResult r = fdem_check(kBadDir + "does_not_exist.yaml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find("no such scene file"), std::string::npos) << r.stderr_text;
}

TEST(BadScene, DirectoryGivenAsTheSceneIsReportedAsADirectory) {
  const CommandResult r = fdem_check(kBadDir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find("is a directory, not a scene file"), std::string::npos) << r.stderr_text;
  EXPECT_EQ(r.stderr_text.find("no such scene file"), std::string::npos) << r.stderr_text;
}

TEST(BadScene, CommandLineErrorsExit2) {
  const std::string command = std::string(FDEM_EXE) + " run --threads 0 x.yaml >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
  const int unknown = std::system((std::string(FDEM_EXE) + " frobnicate >/dev/null 2>&1").c_str());
  EXPECT_EQ(WIFEXITED(unknown) ? WEXITSTATUS(unknown) : -1, 2);
}

}  // namespace
}  // namespace fdem
