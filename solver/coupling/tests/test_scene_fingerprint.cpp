// The checkpoint's scene fingerprint is derived from the scene schema
// (scene/scene_schema.hpp, scene/scene_key_values.hpp): every leaf key of
// the schema either has its value in the fingerprint or is exempt with a
// reason, and changing any key that changes a step changes the fingerprint's
// hash and the entry a refusal names. A key added to the schema without a
// value (or without a changed value below) fails these tests. The words of
// every choice key are held to the loader and to the enumerations here too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "coupling/checkpoint_format.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_key_values.hpp"
#include "scene/scene_overrides.hpp"
#include "scene/scene_schema.hpp"
#include "scene/tests/every_key_scene.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

// One change per leaf key of the schema on scene_test::kEveryKeyScene: the
// key it tests, the override that makes it (a key path of the file and its
// new YAML value).
struct Change {
  std::string schema_key;
  std::string override_key;
  std::string value;
  std::vector<SceneOverride> with = {};  // further overrides the change needs to load
};

// coupling.source_form: paper and fluid.scheme: projection are the simplified
// model's only (the loader refuses them with vans_a, the every-key scene's model).
const SceneOverride kSimplifiedModel{"fluid.model", "simplified", "paper source form needs the simplified model"};

const std::vector<Change> kChanges = {
    {"title", "title", "another title"},
    {"domain.lower", "domain.lower", "[-0.001, 0, 0]"},
    {"domain.upper", "domain.upper", "[0.01, 0.011, 0.02]"},
    {"mesh.cells", "mesh.cells", "[2, 2, 5]"},
    {"mesh.cell_size", "mesh", "{cell_size: 0.0025}"},
    {"gravity", "gravity", "[0, 0, -9.8]"},
    {"effects.fluid", "effects", "{fluid: false, tangential_contact: true, rotation: true}"},
    {"effects.coupling", "effects.coupling", "fluid_to_particle"},
    {"effects.gravity", "effects.gravity", "false"},
    {"effects.buoyancy", "effects.buoyancy", "false"},
    {"effects.drag", "effects.drag", "stokes"},
    {"effects.normal_contact", "effects", "{normal_contact: false}"},
    {"effects.tangential_contact", "effects.tangential_contact", "false"},
    {"effects.rotation", "effects.rotation", "false"},
    {"effects.walls", "effects.walls", "false"},
    {"fluid.density", "fluid.density", "1001"},
    {"fluid.viscosity", "fluid.viscosity", "1.1e-3"},
    {"fluid.time_scheme", "fluid.time_scheme", "bdf1"},
    {"fluid.scheme", "fluid.scheme", "projection", {kSimplifiedModel}},
    {"fluid.model", "fluid.model", "vans_b"},
    {"fluid.porosity_time_derivative", "fluid.porosity_time_derivative", "true"},
    {"fluid.boundaries.x_min", "fluid.boundaries.x_min", "no_slip"},
    {"fluid.boundaries.x_max", "fluid.boundaries.x_max", "free_slip"},
    {"fluid.boundaries.y_min", "fluid.boundaries.y_min", "no_slip"},
    {"fluid.boundaries.y_max", "fluid.boundaries.y_max", "outlet"},
    {"fluid.boundaries.z_min", "fluid.boundaries.z_min", "free_slip"},
    {"fluid.boundaries.z_max", "fluid.boundaries.z_max", "free_slip"},
    {"fluid.boundaries.<face>.type", "fluid.boundaries.z_max", "{type: free_slip}"},
    {"fluid.boundaries.<face>.velocity", "fluid.boundaries.x_min.velocity", "[0.02, 0, 0]"},
    {"fluid.boundaries.<face>.above", "fluid.boundaries.x_min.above", "0.002"},
    {"fluid.boundaries.<face>.superficial", "fluid.boundaries.x_min.superficial", "false"},
    {"fluid.solver.linear_tolerance", "fluid.solver.linear_tolerance", "1.0e-9"},
    {"fluid.solver.max_linear_iterations", "fluid.solver.max_linear_iterations", "999"},
    {"fluid.solver.picard_tolerance", "fluid.solver.picard_tolerance", "1.0e-7"},
    {"fluid.solver.max_picard_iterations", "fluid.solver.max_picard_iterations", "11"},
    {"fluid.solver.linearization", "fluid.solver.linearization", "picard"},
    {"fluid.solver.linear_solver", "fluid.solver.linear_solver", "petsc"},
    {"fluid.solver.petsc_options", "fluid.solver", "{linear_solver: petsc, petsc_options: '-ksp_type gmres'}"},
    {"particles", "particles[2]", "{placement: single, position: [0.002, 0.002, 0.015], size: 1.0e-3, density: 2500}"},
    {"particles[].name", "particles[0].name", "renamed"},
    {"particles[].placement", "particles[1]", "{placement: random, count: 1, region: {lower: [0.001, 0.001, 0.013], "
                                              "upper: [0.009, 0.009, 0.017]}, size: 1.0e-3, density: 2500}"},
    {"particles[].position", "particles[1].position", "[0.005, 0.005, 0.016]"},
    {"particles[].region.lower", "particles[0].region.lower", "[0.001, 0.001, 0.0015]"},
    {"particles[].region.upper", "particles[0].region.upper", "[0.009, 0.009, 0.0055]"},
    {"particles[].lattice", "particles[0].lattice", "[2, 2, 1]"},
    {"particles[].count", "particles[2].count", "3"},
    {"particles[].file", "particles[1]", "{placement: csv, file: grains.csv}"},
    {"particles[].size.distribution", "particles[1].size", "{distribution: uniform, min: 1.0e-3, max: 1.1e-3}"},
    {"particles[].size.diameter", "particles[1].size.diameter", "1.1e-3"},
    {"particles[].size.min", "particles[0].size.min", "1.1e-3"},
    {"particles[].size.max", "particles[0].size.max", "1.4e-3"},
    {"particles[].size.mean", "particles[2].size.mean", "1.05e-3"},
    {"particles[].size.sd", "particles[2].size.sd", "1.5e-4"},
    {"particles[].density", "particles[0].density", "2600"},
    {"particles[].velocity", "particles[0].velocity", "[0, 0, -0.02]"},
    {"particles[].seed", "particles[2].seed", "6"},
    {"contact.kn", "contact.kn", "101"},
    {"contact.cn", "contact.cn", "1.1e-3"},
    {"contact.restitution", "contact", "{kn: 100, restitution: 0.5, kt: 50, ct: 1.0e-4, friction: 0.3}"},
    {"contact.kt", "contact.kt", "51"},
    {"contact.ct", "contact.ct", "2.0e-4"},
    {"contact.friction", "contact.friction", "0.4"},
    {"contact.allow_unstable_step", "contact.allow_unstable_step", "true"},
    {"time.fluid_step", "time.fluid_step", "2.0e-3"},
    {"time.dem_step", "time.dem_step", "2.0e-5"},
    {"time.subcycles", "time", "{fluid_step: 1.0e-3, dem_step: 2.0e-5, subcycles: 50, end: 0.01}"},
    {"time.end", "time.end", "0.02"},
    {"coupling.porosity", "coupling.porosity", "shape_function"},
    {"coupling.porosity_floor", "coupling.porosity_floor", "0.2"},
    {"coupling.porosity_smoothing_length", "coupling.porosity_smoothing_length", "0.004"},
    // Not with porosity_smoothing_length (the loader refuses both): the coupling map without it.
    {"coupling.porosity_smoothing_diameters", "coupling",
     "{porosity: diffused, porosity_floor: 0.1, porosity_smoothing_diameters: 3, source_form: conservative, "
     "exchange: semi_implicit, freeze_until: 0.002}"},
    {"coupling.source_form", "coupling.source_form", "paper", {kSimplifiedModel}},
    {"coupling.exchange", "coupling.exchange", "explicit"},
    {"coupling.freeze_until", "coupling.freeze_until", "0.003"},
    {"output.directory", "output.directory", "elsewhere"},
    {"output.vtu_interval", "output.vtu_interval", "0.002"},
    {"output.vtu_format", "output.vtu_format", "ascii"},
    {"output.csv_interval", "output.csv_interval", "0.002"},
    {"output.checkpoint_interval", "output.checkpoint_interval", "0.002"},
    {"output.probes", "output.probes", "[count]"},
};

// The schema path of a fingerprint entry: its name without a vector's
// component, faces as `<face>`.
std::string entry_key(const std::string& name) {
  for (const char* axis : {".x", ".y", ".z"})
    if (name.ends_with(axis) && is_scene_key(name.substr(0, name.size() - 2)))
      return schema_path_of(name.substr(0, name.size() - 2));
  return schema_path_of(name);
}

class SceneFingerprintTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test case: ctest runs the cases as parallel processes.
    dir_ = fs::path(FDEM_BINARY_DIR) / "test_scene_fingerprint" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir_);
    std::ofstream(dir_ / "scene.yaml") << scene_test::kEveryKeyScene;
    std::ofstream(dir_ / "grains.csv") << "id,d,rho,x,y,z\n1,1.0e-3,2500,0.005,0.005,0.015\n2,1.0e-3,2500,0.003,0.003,"
                                          "0.015\n";
  }
  checkpoint::SceneFingerprint fingerprint(const std::vector<SceneOverride>& overrides) const {
    Scene scene = load_scene_with_overrides((dir_ / "scene.yaml").string(), overrides);
    const Particles particles = generate_particles(scene);
    return checkpoint::scene_fingerprint(scene, scene.time.subcycles, particles);  // the loader resolved the steps
  }
  fs::path dir_;
};

bool is_leaf(const SceneKey& k) { return !k.is_map; }

TEST_F(SceneFingerprintTest, EveryLeafKeyOfTheSchemaIsInTheFingerprintOrExemptWithAReason) {
  const checkpoint::SceneFingerprint f = fingerprint({});
  std::set<std::string> in_fingerprint;
  for (const auto& [name, value] : f.entries) in_fingerprint.insert(entry_key(name));
  for (const SceneKey& k : scene_schema()) {
    if (!is_leaf(k)) continue;
    const FingerprintExemption* exempt = fingerprint_exemption(k.path);
    if (exempt == nullptr) {
      EXPECT_TRUE(in_fingerprint.contains(std::string(k.path))) << k.path << " is not in the fingerprint";
    } else {
      EXPECT_FALSE(exempt->why.empty()) << k.path;
      if (!exempt->covered_by.empty() && exempt->covered_by != "particles") {
        EXPECT_TRUE(in_fingerprint.contains(std::string(exempt->covered_by)))
            << k.path << " is covered by " << exempt->covered_by << ", which the fingerprint lacks";
      }
    }
  }
  // Nothing in the fingerprint or the value table that the schema lacks or exempts.
  for (const std::string& key : in_fingerprint) {
    if (key == "particles.count") continue;  // the generated particles' count, beside their hash
    EXPECT_TRUE(is_scene_key(key)) << "fingerprint entry " << key << " is not a schema key";
    EXPECT_EQ(fingerprint_exemption(key), nullptr) << key << " is exempt but in the fingerprint";
  }
  for (const std::string& key : keys_with_values()) EXPECT_TRUE(in_fingerprint.contains(key)) << key;
  // Every exemption names keys of the schema.
  for (const FingerprintExemption& e : fingerprint_exemptions()) {
    const bool names_a_key = std::any_of(scene_schema().begin(), scene_schema().end(), [&e](const SceneKey& k) {
      return e.path.ends_with('.') ? k.path.starts_with(e.path) : k.path == e.path;
    });
    EXPECT_TRUE(names_a_key) << "exemption " << e.path << " names no schema key";
  }
}

TEST_F(SceneFingerprintTest, ChangingAnyKeyThatChangesAStepChangesTheHashAndTheEntryARefusalNames) {
  // Every leaf key has a change here; a key added to the schema without one
  // fails. A registered term whose table holds one row (contact.law today)
  // has no other word to change to: ChoiceWordsAreTheLoadersInTheEnumerationsOrder
  // reads its one value back from the fingerprint instead, and the key needs
  // a change here as soon as its table has a second row.
  for (const SceneKey& k : scene_schema()) {
    if (!is_leaf(k)) continue;
    if (choice_words(k.path).size() == 1) continue;
    EXPECT_TRUE(std::any_of(kChanges.begin(), kChanges.end(), [&k](const Change& c) { return c.schema_key == k.path; }))
        << "no change of " << k.path << " is tested: add a row to kChanges";
  }
  const checkpoint::SceneFingerprint base = fingerprint({});
  for (const Change& c : kChanges) {
    SCOPED_TRACE(c.schema_key + ": " + c.override_key + " = " + c.value);
    EXPECT_TRUE(is_scene_key(c.schema_key)) << "not a schema key";
    checkpoint::SceneFingerprint changed;
    try {
      std::vector<SceneOverride> overrides{{c.override_key, c.value, "the key under test"}};
      overrides.insert(overrides.end(), c.with.begin(), c.with.end());
      changed = fingerprint(overrides);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "the changed scene does not load: " << e.what();
      continue;
    }
    const FingerprintExemption* exempt = fingerprint_exemption(c.schema_key);
    if (exempt != nullptr && exempt->covered_by.empty()) {
      EXPECT_EQ(changed.hash(), base.hash()) << "a restart may change this key (" << exempt->why << ")";
      continue;
    }
    EXPECT_NE(changed.hash(), base.hash());
    // The entry a refusal would name differs too (for the particle keys: the hash of the particles).
    const std::string named = exempt != nullptr ? std::string(exempt->covered_by) : c.schema_key;
    if (named == "particles") {
      EXPECT_NE(changed.particle_hash, base.particle_hash);
      continue;
    }
    bool differs = false;
    for (const auto& [name, value] : changed.entries) {
      if (entry_key(name) != named) continue;
      const auto it = std::find_if(base.entries.begin(), base.entries.end(),
                                   [&name](const auto& entry) { return entry.first == name; });
      differs = differs || it == base.entries.end() || std::memcmp(&it->second, &value, sizeof value) != 0;
    }
    EXPECT_TRUE(differs) << "no entry of " << named << " differs";
  }
}

// A choice key's override on the base scene: list items as the first set, a
// face as z_max (a map, so an inlet gets its velocity).
SceneOverride choice_override(const std::string& path, std::string_view word) {
  std::string key = path;
  for (std::size_t at; (at = key.find("[]")) != std::string::npos;) key.replace(at, 2, "[0]");
  if (key == "fluid.boundaries.<face>.type") {
    const std::string velocity = word == "inlet" ? ", velocity: [0, 0, -0.01]" : "";
    return {"fluid.boundaries.z_max", "{type: " + std::string(word) + velocity + "}", "the word under test"};
  }
  return {key, std::string(word), "the word under test"};
}

// The words of every "one of" key are the loader's (its refusal lists them
// in the same order), and word i is the enumeration's value i (read back
// through the fingerprint's value of the key): so `fdem check` and the run's
// summary, which name a setting by choice_word, print what the file says.
TEST_F(SceneFingerprintTest, ChoiceWordsAreTheLoadersInTheEnumerationsOrder) {
  int choice_keys = 0;
  for (const SceneKey& k : scene_schema()) {
    const std::vector<std::string_view> words = choice_words(k.path);
    if (words.empty()) continue;
    ++choice_keys;
    const std::string path(k.path);
    SCOPED_TRACE(path);
    try {
      fingerprint({choice_override(path, "not_a_word")});
      ADD_FAILURE() << "a word outside the schema's was accepted";
    } catch (const InputError& e) {
      std::string listed;
      for (const std::string_view w : words) listed += (listed.empty() ? "" : ", ") + std::string(w);
      EXPECT_NE(std::string(e.what()).find("expected one of: " + listed), std::string::npos) << e.what();
    }
    if (fingerprint_exemption(path) != nullptr) continue;  // no value of its own to read back
    for (std::size_t i = 0; i < words.size(); ++i) {
      checkpoint::SceneFingerprint f;
      try {
        std::vector<SceneOverride> overrides{choice_override(path, words[i])};
        if (path == "coupling.source_form" || path == "fluid.scheme") overrides.push_back(kSimplifiedModel);
        f = fingerprint(overrides);
      } catch (const std::exception& e) {
        ADD_FAILURE() << words[i] << " does not load: " << e.what();
        continue;
      }
      std::string entry = path;
      if (const std::size_t at = entry.find("<face>"); at != std::string::npos) entry.replace(at, 6, "z_max");
      const auto it = std::find_if(f.entries.begin(), f.entries.end(), [&](const auto& e) { return e.first == entry; });
      ASSERT_NE(it, f.entries.end()) << entry;
      EXPECT_EQ(it->second, static_cast<double>(i)) << words[i] << " is not value " << i << " of the enumeration";
      EXPECT_EQ(choice_word(path, i), words[i]);
    }
  }
  EXPECT_GE(choice_keys, 12) << "the schema's choice keys (scene_schema.cpp)";
}

}  // namespace
}  // namespace fdem
