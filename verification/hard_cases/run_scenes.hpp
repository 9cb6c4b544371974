#pragma once
// Scene files for the `fdem run` hard cases (output folder, durable probes,
// run diagnostics). Test code only.
#include <string>

namespace fdem::hard {

/// examples/dry_drop.yaml's 27 beads in a 1 cm walled box, stepped one DEM
/// step of 1e-5 s at a time to `end_s`; `output` is the output block's body
/// (after `directory: out`); `walls` false opens the box.
inline std::string dry_drop_yaml(double end_s, const std::string& output = "", const std::string& title = "dry drop",
                                 bool walls = true) {
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
         "time: {dem_step: 1.0e-5, end: " +
         std::to_string(end_s) + "}\noutput: {directory: out" + output + "}\n";
}

}  // namespace fdem::hard
