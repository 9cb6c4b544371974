// Checkpoint payload of the coupled run: sections "SIM ", "DEM ", and with
// fluid "FLUI", "COUP" (layout in coupling/checkpoint_format.hpp; field
// order = the order of the writes). The file around the payload (header,
// scene fingerprint, length, checksum, end marker) is checkpoint_format.cpp's.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <ostream>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "coupling/simulation_impl.hpp"

namespace fdem {

namespace {

bool bitwise_equal(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}

// Decomposed over MPI ranks a field summed over grains is each rank's owned
// grains' partial sum added over the ranks (parallel/grain_share.hpp). The
// writer's owners are those of its last redistribution, the reader's those
// of the loaded positions: grains that crossed a slab face in between are
// counted in the other rank's partial sum, which changes the rounding of
// the elements they touch (a few ulp of the field's largest value; 1e-12
// leaves a factor 1e3 for the grains summed into one element and still
// refuses another scene or a corrupt file).
constexpr double kRegroupedSumTolerance = 1e-12;
bool equal_up_to_regrouping(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) return false;
  double scale = 0.0;
  for (double v : b) scale = std::max(scale, std::abs(v));
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!(std::abs(a[k] - b[k]) <= kRegroupedSumTolerance * scale)) return false;
  return true;
}

}  // namespace

// Whether the source term now handed to the fluid was built from the mean
// drag of the last step (else it is zero): the branch step 5 took, asked
// with the step's own predicate; right after a restart, the file's flag.
bool Simulation::Impl::source_from_drag() const {
  if (restored_at_step == step_index) return restored_source_from_drag;
  return step_index > 0 && builds_source_from_drag(frozen_at(step_index - 1));
}

void Simulation::Impl::write_payload(std::ostream& out) const {
  checkpoint::Writer w(out);
  w.section("SIM ", 2);
  w.i64(step_index);
  w.f64(step_size);
  w.i64(subcycles);
  w.boolean(fluid != nullptr);
  // Version 2: the grains' slab cut (inner boundaries; none in one process),
  // so a resumed run goes on with the writer's decomposition.
  std::vector<double> cut;
  if (grains != nullptr)
    for (int b = 1; b < grains->ranks(); ++b) cut.push_back(grains->slabs().boundary(b));
  w.doubles(cut);
  dem->save_state(out);
  if (!fluid) return;
  fluid->save_state(out);
  w.section("COUP", 1);
  w.i64(diag.floored_elements);
  w.i64(diag.floored_element_updates);
  w.f64(diag.min_porosity);
  w.vec3(diag.drag_on_particles);
  w.vec3(diag.force_on_fluid);
  w.f64(diag.momentum_imbalance);
  w.i64(diag.particles_outside_mesh);
  w.doubles(porosity->values());
  const bool from_drag = source_from_drag();
  w.boolean(from_drag);
  if (from_drag) {
    std::vector<std::vector<double>> mean_drag;
    if (restored_at_step == step_index) {
      mean_drag.assign(restored_mean_drag.begin(), restored_mean_drag.end());
    } else {
      for (const auto& v : {drag->mean_drag_x(), drag->mean_drag_y(), drag->mean_drag_z()})
        mean_drag.emplace_back(v.begin(), v.end());
    }
    // Decomposed over MPI ranks: every rank's owned grains' in ascending id,
    // the order of the DEM section's whole set (a collective: every rank writes its file).
    if (share().decomposed()) mean_drag = dem->exchange()->gather_owned_arrays(dem->particles(), mean_drag);
    for (const auto& v : mean_drag) w.doubles(v);
  }
  w.doubles(source ? source->nodal_force_density() : std::span<const double>{});
}

void Simulation::Impl::read_payload(std::istream& in) {
  checkpoint::Reader r(in);
  const std::uint32_t sim_version = r.section("SIM ", 2);
  const std::int64_t steps = r.i64("the step index");
  const double size = r.f64("the step size");
  const std::int64_t cycles = r.i64("the subcycle count");
  const bool has_fluid = r.boolean("the fluid flag");
  // The writer's slab cut (version 1 has none: the resumed run cuts afresh
  // at its first list build). The file's rank count is this run's
  // (checkpoint::read_file), so is the decision to decompose.
  const std::size_t inner = grains != nullptr ? static_cast<std::size_t>(grains->ranks() - 1) : 0;
  const std::vector<double> cut = sim_version >= 2 ? r.doubles("the slab cut", inner) : std::vector<double>{};
  if (sim_version >= 2 && cut.size() != inner)
    throw SolverError(fmt::format("checkpoint: a slab cut of {} boundaries, this run has {}", cut.size(), inner));
  if (grains != nullptr && !cut.empty()) {
    try {
      grains->restore_cut(cut);
    } catch (const std::invalid_argument& e) {
      throw SolverError(fmt::format("checkpoint: the slab cut: {} (corrupt)", e.what()));
    }
  }
  if (steps < 0) throw SolverError(fmt::format("checkpoint: step index {} (corrupt)", steps));
  if (size != step_size || cycles != subcycles || has_fluid != (fluid != nullptr))
    throw SolverError(fmt::format("checkpoint: step {:.17g} s x {} subcycles (fluid {}), this run {:.17g} s x {} "
                                  "(fluid {})",
                                  size, cycles, has_fluid, step_size, subcycles, fluid != nullptr));
  step_index = static_cast<long>(steps);
  dem->load_state(in);
  if (fluid) {
    fluid->load_state(in);
    r.section("COUP", 1);
    CouplingDiagnostics d = diag;
    d.floored_elements = static_cast<long>(r.i64("the floored element count"));
    d.floored_element_updates = static_cast<long>(r.i64("the floored element total"));
    d.min_porosity = r.f64("the minimum porosity");
    d.drag_on_particles = r.vec3("the drag on the particles");
    d.force_on_fluid = r.vec3("the force on the fluid");
    d.momentum_imbalance = r.f64("the momentum imbalance");
    d.particles_outside_mesh = static_cast<long>(r.i64("the particles outside the mesh"));
    const std::vector<double> saved_porosity =
        r.doubles_exactly("the porosity", static_cast<std::size_t>(mesh->num_elements()));
    // Mapping and porosity are functions of the positions: rebuilt, then
    // checked against the file bit for bit.
    map_and_porosity();
    // With ElementSums a rank holds the fields only where its grains and
    // fluid rows need them; the grains' part follows the slab cut (the
    // file's, moved by the load's rebalance only past its hysteresis): its
    // owned block (the layers of its fluid rows, fixed by the mesh and the
    // rank count) is compared.
    const auto owned_block = [this](std::span<const double> v, bool per_node, std::size_t width) {
      if (!element_sums) return v;
      const auto [first, end] = per_node ? element_sums->owned_nodes() : element_sums->owned_elements();
      if (v.size() < static_cast<std::size_t>(end) * width) return v;  // a short saved array: refused below
      return v.subspan(static_cast<std::size_t>(first) * width, static_cast<std::size_t>(end - first) * width);
    };
    const auto rebuilt_matches = [this, &owned_block](std::span<const double> rebuilt, std::span<const double> saved,
                                                      bool per_node, std::size_t width) {
      if (!share().decomposed()) return bitwise_equal(rebuilt, saved);
      return rebuilt.size() == saved.size() &&
             equal_up_to_regrouping(owned_block(rebuilt, per_node, width), owned_block(saved, per_node, width));
    };
    if (!rebuilt_matches(porosity->values(), saved_porosity, false, 1))
      throw SolverError("checkpoint: the porosity rebuilt from the particles differs from the saved one "
                        "(another scene or build?)");
    // Decomposed over MPI ranks the file holds the whole set (ascending id),
    // this rank its grains and ghosts: each takes its grains' values by id.
    const Particles& here = dem->particles();
    const std::size_t n = share().decomposed() ? dem->whole_particles().size() : here.size();
    restored_source_from_drag = r.boolean("the source-term flag");
    if (restored_source_from_drag && !(source && drag))
      throw SolverError("checkpoint: a source term from drag, but this scene has no two-way exchange");
    for (auto& v : restored_mean_drag) v.clear();
    if (restored_source_from_drag)
      for (auto& v : restored_mean_drag) v = r.doubles_exactly("the mean drag", n);
    if (restored_source_from_drag && share().decomposed()) {
      const std::vector<Index>& whole_ids = dem->whole_particles().id;
      std::array<std::vector<double>, 3> mine;
      for (std::size_t i = 0; i < here.size(); ++i) {
        const auto at = std::lower_bound(whole_ids.begin(), whole_ids.end(), here.id[i]);
        if (at == whole_ids.end() || *at != here.id[i])
          throw SolverError(fmt::format("checkpoint: particle {} of this rank is not in the saved set (corrupt)",
                                        here.id[i]));
        const auto k = static_cast<std::size_t>(at - whole_ids.begin());
        for (std::size_t c = 0; c < 3; ++c) mine[c].push_back(restored_mean_drag[c][k]);
      }
      restored_mean_drag = std::move(mine);
    }
    const std::vector<double> saved_source =
        r.doubles("the source term", 3 * static_cast<std::size_t>(mesh->num_nodes()));
    if (source) {
      if (restored_source_from_drag) {
        source->compute(dem->particles(), mapping, porosity->values(), restored_mean_drag[0],
                        restored_mean_drag[1], restored_mean_drag[2], share());
      } else {
        source->clear();
      }
      if (!rebuilt_matches(source->nodal_force_density(), saved_source, true, 3))
        throw SolverError("checkpoint: the source term rebuilt from the saved drag differs from the saved one "
                          "(another scene or build?)");
    } else if (!saved_source.empty()) {
      throw SolverError("checkpoint: holds a source term, but this scene sends none to the fluid");
    }
    diag = d;
    restored_at_step = step_index;
    if (exchange) prepare_exchange();  // a function of the restored positions, velocities and fluid
  }
  if (in.peek() != std::char_traits<char>::eof())
    throw SolverError("checkpoint: unread data after the last section (another format?)");
}

void Simulation::save_checkpoint(std::ostream& out) const {
  // The payload goes to memory first: its length and checksum lead it in the file.
  std::ostringstream payload(std::ios::out | std::ios::binary);
  impl_->write_payload(payload);
  checkpoint::write_file(out, impl_->fingerprint, payload.view());
}

void Simulation::load_checkpoint(std::istream& in) {
  // Verified whole (scene, length, checksum, end marker) before anything is
  // touched, then read into a fresh run of the same scene, which replaces
  // this one only when every section has been read and checked.
  const std::string payload = checkpoint::read_file(in, impl_->fingerprint);
  auto next = std::make_unique<Impl>(impl_->scene);
  next->dem->set_grain_sort_policy(impl_->dem->grain_sort_policy());  // a run setting, not in the file
  std::istringstream state(payload, std::ios::in | std::ios::binary);
  next->read_payload(state);
  impl_ = std::move(next);
}

}  // namespace fdem
