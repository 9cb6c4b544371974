#pragma once
// The coupled scene the restart tests checkpoint: water driven through a
// 4 x 4 x 4 mm box over 48 grains that settle, touch, slide and spin, so a
// restart must carry every piece of state: positions and velocities, spins,
// tangential slip history, the BDF2 velocity history and the source term.
#include <string>

namespace fdem::restart {

inline std::string coupled_scene_yaml(const std::string& output_extra = "", double end_s = 0.012) {
  return R"(title: restart scene (coupled, tangential contact, rotation, BDF2)
effects: {fluid: true, coupling: two_way, tangential_contact: true, rotation: true}
domain: {lower: [0, 0, 0], upper: [0.004, 0.004, 0.004]}
mesh: {cells: [4, 4, 4]}
fluid:
  density: 1000
  viscosity: 1.0e-3
  time_scheme: bdf2
  boundaries:
    x_min: {type: inlet, velocity: [0.02, 0, 0], above: 0.002}
    x_max: outlet
particles:
  - name: grains
    placement: lattice
    region: {lower: [0, 0, 0], upper: [0.004, 0.004, 0.00135]}
    lattice: [4, 4, 3]
    size: {distribution: uniform, min: 0.35e-3, max: 0.45e-3}
    density: 2650
    velocity: [0.01, 0, -0.02]
    seed: 11
contact: {kn: 50, restitution: 0.5, kt: 20, friction: 0.4}
time: {fluid_step: 1.0e-3, dem_step: 1.0e-5, end: )" +
         std::to_string(end_s) + R"(}
coupling: {porosity: centre, source_form: conservative}
output: {directory: out)" +
         output_extra + R"(}
)";
}

}  // namespace fdem::restart
