// Scene loader: a valid scene reads into the right fields with the documented
// defaults; the derived numbers (cells from cell_size, subcycles) are exact.
// Refusals are covered at length in verification/scene_input.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

const char* kSettling = R"(
title: settling
domain: {lower: [0, 0, 0], upper: [0.044, 0.044, 0.08]}
mesh: {cell_size: 0.004}
fluid:
  density: 1000
  viscosity: 1.0e-3
  boundaries:
    z_max: free_slip
    x_min: {type: inlet, velocity: [0.03, 0, 0], above: 0.002, superficial: true}
    x_max: outlet
particles:
  - name: grain
    placement: single
    position: [0.022, 0.022, 0.07]
    size: 7.6e-4
    density: 2650
contact: {kn: 100, restitution: 0.9}
time: {fluid_step: 0.01, dem_step: 1.0e-5, end: 1.0}
)";

TEST(SceneLoader, ValidSceneReadsEveryGivenValue) {
  const Scene s = load_scene_from_string(kSettling, "settling.yaml");
  EXPECT_EQ(s.title, "settling");
  EXPECT_EQ(s.source_file, "settling.yaml");
  EXPECT_DOUBLE_EQ(s.domain.upper.z(), 0.08);
  EXPECT_EQ(s.fluid.faces[5].condition, FaceCondition::free_slip);
  EXPECT_EQ(s.fluid.faces[0].condition, FaceCondition::inlet);
  EXPECT_DOUBLE_EQ(s.fluid.faces[0].velocity.x(), 0.03);
  EXPECT_DOUBLE_EQ(s.fluid.faces[0].inlet_above_m, 0.002);
  EXPECT_TRUE(s.fluid.faces[0].superficial);
  EXPECT_FALSE(s.fluid.faces[1].superficial);
  EXPECT_EQ(s.fluid.faces[1].condition, FaceCondition::outlet);
  ASSERT_EQ(s.particles.size(), 1u);
  EXPECT_EQ(s.particles[0].size.kind, SizeKind::fixed);
  EXPECT_DOUBLE_EQ(s.particles[0].size.diameter, 7.6e-4);
  ASSERT_TRUE(s.contact.restitution.has_value());
  EXPECT_DOUBLE_EQ(*s.contact.restitution, 0.9);
}

TEST(SceneLoader, CellSizeGivesWholeCellCounts_PaperSettlingBox) {
  // Paper Sect. 4.1: 44 x 44 x 80 mm with 4 mm cells = 11 x 11 x 20 (12100 tets).
  const Scene s = load_scene_from_string(kSettling, "settling.yaml");
  EXPECT_EQ(s.cells[0], 11);
  EXPECT_EQ(s.cells[1], 11);
  EXPECT_EQ(s.cells[2], 20);
  EXPECT_EQ(5 * s.cells[0] * s.cells[1] * s.cells[2], 12100);
}

TEST(SceneLoader, SubcyclesDerivedFromTheSteps) {
  const Scene s = load_scene_from_string(kSettling, "settling.yaml");
  EXPECT_EQ(s.time.subcycles, 1000);  // 0.01 / 1e-5
}

TEST(SceneLoader, DefaultsAreTheDocumentedOnes) {
  const Scene s = load_scene_from_string(kSettling, "settling.yaml");
  const Scene defaults;
  EXPECT_TRUE(s.effects.fluid);
  EXPECT_EQ(s.effects.coupling, CouplingMode::two_way);
  EXPECT_TRUE(s.effects.buoyancy);
  EXPECT_FALSE(s.effects.tangential_contact);
  EXPECT_FALSE(s.effects.rotation);
  EXPECT_EQ(s.fluid.time_scheme, TimeScheme::bdf2);
  EXPECT_EQ(s.fluid.linearization, defaults.fluid.linearization);
  EXPECT_EQ(s.fluid.model, FluidModel::simplified);
  EXPECT_FALSE(s.fluid.porosity_time_derivative);
  EXPECT_EQ(s.fluid.faces[2].condition, FaceCondition::no_slip);  // unnamed faces: no-slip walls
  EXPECT_DOUBLE_EQ(s.gravity.z(), -9.81);
  EXPECT_EQ(s.coupling.porosity, defaults.coupling.porosity);
  EXPECT_DOUBLE_EQ(s.coupling.porosity_floor, defaults.coupling.porosity_floor);
  EXPECT_EQ(s.output.directory, "out");
  EXPECT_EQ(s.particles[0].seed, 1u);
}

TEST(SceneLoader, DryDemSceneNeedsNoMeshFluidOrFluidStep) {
  const char* dry = R"(
effects: {fluid: false}
domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01]}
particles:
  - {name: a, placement: lattice, region: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.005]}, lattice: [4, 4, 2],
     size: {distribution: uniform, min: 1.0e-3, max: 2.0e-3}, density: 2500}
contact: {kn: 1000, cn: 0.01}
time: {dem_step: 1.0e-6, end: 1.0e-3, subcycles: 10}
)";
  const Scene s = load_scene_from_string(dry, "dry.yaml");
  EXPECT_FALSE(s.effects.fluid);
  EXPECT_EQ(s.effects.coupling, CouplingMode::off);  // default follows fluid off
  EXPECT_FALSE(s.effects.buoyancy);
  EXPECT_DOUBLE_EQ(s.time.fluid_step, 1.0e-5);       // driver step = subcycles x dem_step
  EXPECT_EQ(s.time.subcycles, 10);
  EXPECT_EQ(s.particles[0].lattice[0], 4);
}

TEST(SceneLoader, FluidSolverKeysAreRead) {
  std::string text = kSettling;
  text.replace(text.find("  viscosity: 1.0e-3\n"), 19,
               "  viscosity: 1.0e-3\n  solver: {linearization: extrapolated, linear_tolerance: 1.0e-8}\n");
  const Scene s = load_scene_from_string(text, "s.yaml");
  EXPECT_EQ(s.fluid.linearization, FluidLinearization::extrapolated);
  EXPECT_DOUBLE_EQ(s.fluid.linear_tolerance, 1.0e-8);
}

TEST(SceneLoader, FluidModelKeysAreRead) {
  std::string text = kSettling;
  text.replace(text.find("  viscosity: 1.0e-3\n"), 19, "  viscosity: 1.0e-3\n  model: vans_a\n  porosity_time_derivative: true\n");
  const Scene s = load_scene_from_string(text, "s.yaml");
  EXPECT_EQ(s.fluid.model, FluidModel::vans_a);
  EXPECT_TRUE(s.fluid.porosity_time_derivative);
}

TEST(SceneLoader, LinearSolverKeysAreReadAndDefaultToEigen) {
  EXPECT_EQ(load_scene_from_string(kSettling, "s.yaml").fluid.linear_solver,
            FluidLinearSolverChoice::eigen_bicgstab_ilut);
  std::string text = kSettling;
  text.replace(text.find("  viscosity: 1.0e-3\n"), 19,
               "  viscosity: 1.0e-3\n  solver: {linear_solver: petsc, petsc_options: \"-pc_type hypre\"}\n");
  const Scene s = load_scene_from_string(text, "s.yaml");
  EXPECT_EQ(s.fluid.linear_solver, FluidLinearSolverChoice::petsc);
  EXPECT_EQ(s.fluid.petsc_options, "-pc_type hypre");
}

TEST(SceneLoader, PetscOptionsAreRefusedWithoutPetscOrWhenNotOptions) {
  for (const char* solver : {"{petsc_options: \"-pc_type hypre\"}", "{linear_solver: petsc, petsc_options: pc_type}",
                             "{linear_solver: petsc_gamg}"}) {
    std::string text = kSettling;
    text.replace(text.find("  viscosity: 1.0e-3\n"), 19, std::string("  viscosity: 1.0e-3\n  solver: ") + solver + "\n");
    try {
      (void)load_scene_from_string(text, "s.yaml");
      FAIL() << "accepted fluid.solver " << solver;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("s.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find("fluid.solver."), std::string::npos) << what;
    }
  }
}

TEST(SceneLoader, BareOffReadsAsCouplingModeNotBoolean) {
  // YAML 1.1 reads `off` as a boolean; the loader takes the scalar text.
  std::string text = kSettling;
  text.insert(0, "effects: {coupling: off}\n");
  EXPECT_EQ(load_scene_from_string(text, "s.yaml").effects.coupling, CouplingMode::off);
}

TEST(SceneLoader, VtuFormatIsBinaryUnlessAsciiIsAsked) {
  EXPECT_EQ(load_scene_from_string(kSettling, "s.yaml").output.vtu_format, VtuFormat::binary);
  const std::string ascii = std::string(kSettling) + "output: {vtu_format: ascii}\n";
  EXPECT_EQ(load_scene_from_string(ascii, "s.yaml").output.vtu_format, VtuFormat::ascii);
  try {
    (void)load_scene_from_string(std::string(kSettling) + "output: {vtu_format: text}\n", "s.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "output.vtu_format");
    EXPECT_NE(std::string(e.what()).find("binary, ascii"), std::string::npos) << e.what();
  }
}

TEST(SceneLoader, MissingFileIsAnInputErrorNamingIt) {
  try {
    (void)load_scene("/nonexistent/scene.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/scene.yaml");
    EXPECT_NE(std::string(e.what()).find("no such scene file"), std::string::npos);
  }
}

TEST(SceneLoader, DirectoryIsReportedAsADirectory) {
  try {
    (void)load_scene(FDEM_SOURCE_DIR "/examples");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "(file)");
    EXPECT_NE(std::string(e.what()).find("is a directory, not a scene file"), std::string::npos) << e.what();
  }
}

TEST(SceneLoader, ErrorCarriesOneBasedLineOfTheValue) {
  std::string text = kSettling;
  const auto at = text.find("viscosity: 1.0e-3");
  text.replace(at, 17, "viscosity: 0");
  try {
    (void)load_scene_from_string(text, "s.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "fluid.viscosity");
    EXPECT_EQ(e.value(), "0");
    EXPECT_EQ(e.line(), 7);  // kSettling starts with a newline: the viscosity is on line 7
  }
}

}  // namespace
}  // namespace fdem
