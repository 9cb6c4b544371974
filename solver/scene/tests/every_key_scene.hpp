#pragma once
// A scene file that gives every key it can and reaches every map the loader
// reads (one particle set per placement and size kind; inlet, outlet and
// free-slip faces, one given as a map; tangential contact; the diffused
// porosity scheme; the volume-averaged model), so a test can probe each map
// and change each key from a set value. Shared by the fingerprint tests
// (solver/coupling/tests) and the schema tests (verification/scene_input).
// Test code only.

namespace fdem::scene_test {

inline constexpr const char* kEveryKeyScene = R"(title: every key
domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.02]}
mesh: {cells: [2, 2, 4]}
gravity: [0, 0, -9.81]
effects: {fluid: true, coupling: two_way, gravity: true, buoyancy: true, drag: ergun_wen_yu, normal_contact: true,
          tangential_contact: true, rotation: true, walls: true}
fluid:
  density: 1000
  viscosity: 1.0e-3
  time_scheme: bdf2
  model: vans_a
  porosity_time_derivative: false
  boundaries:
    x_min: {type: inlet, velocity: [0.01, 0, 0], above: 0.001, superficial: true}
    x_max: outlet
    y_min: free_slip
    y_max: free_slip
    z_min: no_slip
    z_max: no_slip
  solver: {linear_tolerance: 1.0e-8, max_linear_iterations: 1000, picard_tolerance: 1.0e-8,
           max_picard_iterations: 10, linearization: extrapolated}
particles:
  - name: lattice
    placement: lattice
    region: {lower: [0.001, 0.001, 0.001], upper: [0.009, 0.009, 0.005]}
    lattice: [2, 2, 2]
    size: {distribution: uniform, min: 1.0e-3, max: 1.5e-3}
    density: 2500
    velocity: [0, 0, -0.01]
    seed: 3
  - name: single
    placement: single
    position: [0.005, 0.005, 0.015]
    size: {distribution: fixed, diameter: 1.0e-3}
    density: 2500
  - name: random
    placement: random
    count: 4
    region: {lower: [0.001, 0.001, 0.008], upper: [0.009, 0.009, 0.012]}
    size: {distribution: normal, mean: 1.0e-3, sd: 1.0e-4, min: 8.0e-4, max: 1.2e-3}
    density: 2500
    seed: 5
contact: {law: linear_spring_dashpot, kn: 100, cn: 1.0e-3, kt: 50, ct: 1.0e-4, friction: 0.3,
          allow_unstable_step: false}
time: {fluid_step: 1.0e-3, dem_step: 1.0e-5, end: 0.01}
coupling: {porosity: diffused, porosity_floor: 0.1, porosity_smoothing_length: 0.005, source_form: conservative,
           exchange: semi_implicit, freeze_until: 0.002}
output: {directory: out, vtu_interval: 0.005, vtu_format: binary, csv_interval: 0.001, checkpoint_interval: 0.005,
         probes: [count, mean_position]}
)";

}  // namespace fdem::scene_test
