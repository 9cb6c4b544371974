#pragma once
// Scene files for the tests that spawn `fdem run` (hard cases: output folder,
// durable probes, run diagnostics; verification/restart). Test code only.
#include <string>

#include <fmt/format.h>

namespace fdem::hard {

/// examples/dry_drop.yaml's 27 beads in a 1 cm walled box, stepped
/// `subcycles` DEM steps of 1e-5 s at a time (0: one) to `end_s`; `output` is
/// the output block's body (after `directory: out`); `walls` false opens the box.
inline std::string dry_drop_yaml(double end_s, const std::string& output = "", const std::string& title = "dry drop",
                                 bool walls = true, int subcycles = 0) {
  return "title: " + title +
         "\n"
         "effects: {fluid: false, gravity: true, normal_contact: true, walls: " +
         std::string(walls ? "true" : "false") +
         "}\n"
         "domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01]}\n"
         "particles:\n"
         "  - name: beads\n"
         "    placement: lattice\n"
         "    region: {lower: [0.002, 0.002, 0.004], upper: [0.008, 0.008, 0.010]}\n"
         "    lattice: [3, 3, 3]\n"
         "    size: {distribution: uniform, min: 1.0e-3, max: 1.5e-3}\n"
         "    density: 2500\n"
         "    seed: 42\n"
         "contact: {kn: 100, restitution: 0.5}\n"
         "time: {dem_step: 1.0e-5, " +
         (subcycles > 0 ? "subcycles: " + std::to_string(subcycles) + ", " : std::string()) + "end: " +
         std::to_string(end_s) + "}\noutput: {directory: out" + output + "}\n";
}

/// Still water (no inlet, no grains, no gravity) in a box from the origin to
/// `upper` [m] of `cells` cells a side, fluid step 1e-3 s to `end_s`: a scene
/// whose cost is its mesh alone.
inline std::string still_water_yaml(const std::string& upper, const std::string& cells, double end_s) {
  return "effects: {fluid: true, coupling: off, gravity: false}\n"
         "domain: {lower: [0, 0, 0], upper: " + upper + "}\n"
         "mesh: {cells: " + cells + "}\n"
         "fluid: {density: 1000, viscosity: 1.0e-3}\n"
         "time: {fluid_step: 1.0e-3, end: " + fmt::format("{}", end_s) + "}\n"
         "output: {directory: out}\n";
}

}  // namespace fdem::hard
