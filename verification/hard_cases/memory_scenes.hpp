#pragma once
// Scenes for the memory checks: `fdem check`'s estimate against the peak RSS
// of `fdem run`, and the refusal of a scene larger than the machine.
#include <string>

namespace fdem::hard {

/// `count` grains of 1-1.5 mm drawn at random in a walled cube of `edge_m`,
/// five DEM steps; `output` adds keys to the output block.
inline std::string random_grains_yaml(long count, double edge_m, const std::string& output = "") {
  const std::string e = std::to_string(edge_m);
  return "effects: {fluid: false, gravity: true, normal_contact: true, walls: true}\n"
         "domain: {lower: [0, 0, 0], upper: [" + e + ", " + e + ", " + e + "]}\n"
         "particles:\n"
         "  - {name: g, placement: random, region: {lower: [0, 0, 0], upper: [" + e + ", " + e + ", " + e +
         "]}, count: " + std::to_string(count) +
         ", size: {distribution: uniform, min: 1.0e-3, max: 1.5e-3}, density: 2500, seed: 1}\n"
         "contact: {kn: 100, restitution: 0.5}\n"
         "time: {dem_step: 1.0e-5, end: 5.0e-5}\n"
         "output: {directory: out" + output + "}\n";
}

/// Water driven along x through a 0.1 m cube of `cells`^3 cells for three
/// 1 ms steps, with `count` grains of 0.5-0.7 mm in its lower half (two-way
/// coupling) or none.
inline std::string water_cube_yaml(int cells, long count) {
  const std::string c = std::to_string(cells);
  std::string yaml = "effects: {fluid: true, coupling: " + std::string(count > 0 ? "two_way" : "off") +
                     ", gravity: true}\n"
                     "domain: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.1]}\n"
                     "mesh: {cells: [" + c + ", " + c + ", " + c + "]}\n"
                     "fluid:\n  density: 1000\n  viscosity: 1.0e-3\n  boundaries:\n"
                     "    x_min: {type: inlet, velocity: [0.01, 0, 0]}\n    x_max: outlet\n";
  if (count > 0)
    yaml += "particles:\n  - {name: g, placement: random, region: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.05]}, count: " +
            std::to_string(count) +
            ", size: {distribution: uniform, min: 0.5e-3, max: 0.7e-3}, density: 2500, seed: 1}\n"
            "contact: {kn: 100, restitution: 0.5}\n";
  yaml += std::string("time: {fluid_step: 1.0e-3") + (count > 0 ? ", dem_step: 2.5e-5" : "") +
          ", end: 3.0e-3}\noutput: {directory: out}\n";
  return yaml;
}

}  // namespace fdem::hard
