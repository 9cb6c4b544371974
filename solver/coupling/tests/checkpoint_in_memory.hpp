#pragma once
// A checkpoint held in memory as bytes (Simulation::save_checkpoint /
// load_checkpoint over string streams), for tests that restart, compare or
// corrupt it without touching the disk: the runs restarted through it, and
// the straight runs they are compared with. Shared by
// solver/coupling/tests/test_checkpoint.cpp and verification/restart.
// Test code only.
#include <sstream>
#include <string>
#include <utility>

#include "coupling/simulation.hpp"

namespace fdem::checkpoint_test {

/// The checkpoint `sim` writes at its current step.
inline std::string checkpoint_bytes(const Simulation& sim) {
  std::ostringstream out(std::ios::out | std::ios::binary);
  sim.save_checkpoint(out);
  return out.str();
}

/// Loads `bytes` into `sim`; refuses (throws) as Simulation::load_checkpoint does.
inline void load_checkpoint_bytes(Simulation& sim, const std::string& bytes) {
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  sim.load_checkpoint(in);
}

/// A fresh run of `scene` resumed from `bytes`.
inline Simulation resumed_from(const Scene& scene, const std::string& bytes) {
  Simulation resumed(scene);
  load_checkpoint_bytes(resumed, bytes);
  return resumed;
}

/// `scene` run `steps` steps without a checkpoint.
inline Simulation straight_run(const Scene& scene, int steps) {
  Simulation sim(scene);
  for (int k = 0; k < steps; ++k) sim.step();
  return sim;
}

/// `scene` run `steps_before` steps and checkpointed; a fresh run resumed
/// from that checkpoint and stepped `steps_after` steps more.
inline Simulation restarted_run(const Scene& scene, int steps_before, int steps_after) {
  const Simulation first_part = straight_run(scene, steps_before);
  Simulation resumed = resumed_from(scene, checkpoint_bytes(first_part));
  for (int k = 0; k < steps_after; ++k) resumed.step();
  return resumed;
}

/// The checkpoint of `scene` after `steps` steps, and what a fresh run that
/// loaded it writes again at once.
struct CheckpointRewrite {
  std::string first, rewritten;
};
inline CheckpointRewrite checkpoint_read_back_and_rewritten(const Scene& scene, int steps) {
  std::string first = checkpoint_bytes(straight_run(scene, steps));
  std::string rewritten = checkpoint_bytes(resumed_from(scene, first));
  return {std::move(first), std::move(rewritten)};
}

}  // namespace fdem::checkpoint_test
