// A coupled run that blows up says which step is at fault. A fluid step far
// above the drag-exchange bound over a packed bed (the DEM step at 0.36 of its
// contact bound, as `fdem check` prints) is named as the fluid step's fault,
// with the step to reduce it to, not as "the DEM step is above the stable
// bound"; at a fluid step below that bound the same bed runs.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "coupling/simulation.hpp"
#include "scene/scene_loader.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

// Water entering at 5 cm/s through an 8 mm box of 2 mm cells, over a bed of
// 8 x 8 x 4 touching 0.99 mm grains filling its lower half (porosity at the
// floor 0.1 in the bed's elements: cell/d = 2). Ergun's viscous K there is
// 150 (1 - eps) mu / (eps d^2) = 1.4e6 kg/(m^3 s): the explicit source
// relaxes the fluid at thousands per second, so a fluid step of 0.1 s is
// hundreds of times its bound. Contacts: Kn 200 N/m, dt_dem 2e-5 s = 0.36 of
// the contact bound.
Scene packed_bed(const std::string& name, double fluid_step_s, double end_s) {
  const auto dir = hard::scratch_dir(name);
  hard::write_text(dir / "scene.yaml", R"(effects: {fluid: true, coupling: two_way, gravity: true}
domain: {lower: [0, 0, 0], upper: [0.008, 0.008, 0.008]}
mesh: {cells: [4, 4, 4]}
fluid:
  density: 1000
  viscosity: 1.0e-3
  boundaries:
    x_min: {type: inlet, velocity: [0.05, 0, 0]}
    x_max: outlet
    z_max: outlet
particles:
  - {name: bed, placement: lattice, region: {lower: [0, 0, 0], upper: [0.008, 0.008, 0.004]}, lattice: [8, 8, 4], size: 0.99e-3, density: 2500}
contact: {kn: 200, restitution: 0.5}
time: {fluid_step: )" + std::to_string(fluid_step_s) +
                                               ", dem_step: 2.0e-5, end: " + std::to_string(end_s) + "}\n");
  return load_scene((dir / "scene.yaml").string());
}

TEST(CoupledBlowUp, FluidStepAboveTheDragExchangeBoundIsNamedAsTheFluidStepsFault) {
  Simulation sim(packed_bed("blow_up_fluid_step", 0.1, 2.0));
  std::string what;
  try {
    while (!sim.finished()) sim.step();
  } catch (const SolverError& e) {
    what = e.what();
  }
  ASSERT_FALSE(what.empty()) << "a fluid step hundreds of times the exchange bound must blow up";
  EXPECT_NE(what.find("the fluid step 0.1 s is at fault"), std::string::npos) << what;
  EXPECT_NE(what.find("reduce time.fluid_step below"), std::string::npos) << what;
  EXPECT_EQ(what.find("is above the stable bound"), std::string::npos) << "the DEM step is not blamed: " << what;
  EXPECT_NE(what.find("contacts dt_dem / stable bound = 0.355"), std::string::npos) << what;
}

TEST(CoupledBlowUp, TheSameBedAtAFluidStepBelowTheBoundRuns) {
  // The bound the message gives for this bed is 1.3e-4 s; at 1e-4 s, 200 steps run and stay bounded.
  Simulation sim(packed_bed("blow_up_below_bound", 1.0e-4, 0.02));
  EXPECT_NO_THROW(while (!sim.finished()) sim.step());
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    EXPECT_LT(std::abs(sim.particles().vx[i]), 0.05) << "no grain faster than the inflow";
}

}  // namespace
}  // namespace fdem
