#include "coupling/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <istream>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "coupling/checkpoint_format.hpp"
#include "coupling/drag_coupling.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/source_term.hpp"
#include "dem/stability.hpp"
#include "fluid/fluid_solver.hpp"
#include "scene/particle_generator.hpp"

namespace fdem {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

bool drag_on_particles(CouplingMode m) { return m == CouplingMode::fluid_to_particle || m == CouplingMode::two_way; }
bool source_on_fluid(CouplingMode m) { return m == CouplingMode::particle_to_fluid || m == CouplingMode::two_way; }

// A fluid that starts at rest, receives no body force and has homogeneous
// boundary data (walls, outlets, inlets of zero velocity) stays exactly at
// rest: u = 0, p = 0 solves the discrete equations of every step. Then the
// solve is skipped (fluid-to-particle settling in still water costs only DEM).
bool fluid_stays_at_rest(const Scene& s) {
  if (source_on_fluid(s.effects.coupling)) return false;
  for (const FaceBoundary& f : s.fluid.faces)
    if (f.condition == FaceCondition::inlet && f.velocity.norm() != 0.0) return false;
  return true;
}

// The scene as the DEM engine must see it (its step derived when the scene
// gives only subcycles), and the number of subcycles per fluid step.
struct StepPlan {
  Scene scene;
  double step_size = 0.0;
  int subcycles = 1;
};

StepPlan plan_steps(const Scene& in, const Particles& particles) {
  StepPlan plan{in, 0.0, 1};
  TimeSpec& t = plan.scene.time;
  const std::string& file = in.source_file;
  if (!in.effects.fluid && t.fluid_step <= 0.0) {  // dry scene stepped one DEM step at a time
    if (t.dem_step <= 0.0) throw InputError(file, "time.dem_step", fmt::format("{}", t.dem_step), "must be > 0 without fluid");
    plan.step_size = t.dem_step;
    return plan;
  }
  if (t.fluid_step <= 0.0) throw InputError(file, "time.fluid_step", fmt::format("{}", t.fluid_step), "must be > 0");
  plan.step_size = t.fluid_step;
  if (t.subcycles > 0) {
    plan.subcycles = t.subcycles;
    const double implied = t.fluid_step / t.subcycles;
    if (t.dem_step <= 0.0) {
      t.dem_step = implied;
    } else if (std::abs(t.dem_step - implied) > 1e-9 * implied) {
      throw InputError(file, "time.subcycles", std::to_string(t.subcycles),
                       fmt::format("fluid_step / subcycles = {:g} s differs from time.dem_step = {:g} s; give one of them",
                                   implied, t.dem_step));
    }
    return plan;
  }
  if (t.dem_step <= 0.0) {
    // Neither given: the largest stable DEM step that divides the fluid step.
    if (particles.size() == 0) {
      t.dem_step = t.fluid_step;
    } else {
      const StabilityReport report = analyse_stability(in.contact, in.effects, mass_range(particles), t.fluid_step,
                                                       in.effects.walls);
      const double stable = report.stable_step_s();
      const int n = std::max(1, static_cast<int>(std::ceil(t.fluid_step / stable - 1e-9)));
      t.dem_step = t.fluid_step / n;
    }
  }
  const double ratio = t.fluid_step / t.dem_step;
  const long n = std::lround(ratio);
  if (n < 1 || std::abs(ratio - static_cast<double>(n)) > 1e-6 * ratio)
    throw InputError(file, "time.dem_step", fmt::format("{:g}", t.dem_step),
                     fmt::format("the fluid step {:g} s must be a whole number of DEM steps (ratio {:g})", t.fluid_step,
                                 ratio));
  plan.subcycles = static_cast<int>(n);
  return plan;
}

}  // namespace

struct Simulation::Impl {
  Scene scene;               // as given, with the DEM step resolved
  double step_size = 0.0;    // [s]
  int subcycles = 1;
  long steps_to_end = 0;
  long step_index = 0;

  std::optional<DemEngine> dem;
  // Fluid side: exists only when scene.effects.fluid.
  std::unique_ptr<BoxMesh> mesh;
  std::unique_ptr<FluidSolver> fluid;
  ParticleMapping mapping;
  std::unique_ptr<PorosityField> porosity;
  std::unique_ptr<DragCoupling> drag;     // only when some drag is exchanged
  std::unique_ptr<SourceTerm> source;
  std::vector<double> zero_source;        // returned by source_term() when the fluid gets nothing
  bool fluid_at_rest = false;             // fluid_stays_at_rest(): no solve needed

  CouplingDiagnostics diag;

  // Checkpoint support: the scene's key numbers (a checkpoint of another
  // scene is refused), and the mean drag a loaded source term was built
  // from, kept until the next step so a checkpoint written right after a
  // restart holds it again.
  checkpoint::SceneFingerprint fingerprint;
  long restored_at_step = -1;
  bool restored_source_from_drag = false;
  std::array<std::vector<double>, 3> restored_mean_drag;

  explicit Impl(const Scene& s) {
    Particles particles = generate_particles(s);
    StepPlan plan = plan_steps(s, particles);
    scene = std::move(plan.scene);
    step_size = plan.step_size;
    subcycles = plan.subcycles;
    steps_to_end = std::lround(std::ceil(scene.time.end_time / step_size - 1e-9));
    fingerprint = checkpoint::scene_fingerprint(scene, subcycles, particles);
    dem.emplace(std::move(particles), scene);
    diag.subcycles = subcycles;

    if (!scene.effects.fluid) return;  // dry scene: no mesh, no fluid, no coupling state
    mesh = std::make_unique<BoxMesh>(scene.domain.lower, scene.domain.upper, scene.cells);
    fluid = std::make_unique<FluidSolver>(*mesh, scene);
    fluid_at_rest = fluid_stays_at_rest(scene);
    porosity = std::make_unique<PorosityField>(*mesh, scene.coupling);
    const CouplingMode mode = scene.effects.coupling;
    if (mode != CouplingMode::off) {
      drag = std::make_unique<DragCoupling>(scene.effects.drag,
                                            FluidProperties{scene.fluid.density, scene.fluid.viscosity},
                                            drag_on_particles(mode));
      dem->set_external_force(drag.get());
    }
    if (source_on_fluid(mode)) source = std::make_unique<SourceTerm>(*mesh, scene.coupling.source_form);
    if (!source) zero_source.assign(3 * static_cast<std::size_t>(mesh->num_nodes()), 0.0);
    map_and_porosity();
  }

  // Fig. 4: particle mapping, then porosity per element.
  void map_and_porosity() {
    mapping.update(*mesh, dem->particles());
    const PorosityUpdate u = porosity->update(dem->particles(), mapping);
    diag.floored_elements = u.floored_elements;
    diag.floored_element_updates += u.floored_elements;
    diag.min_porosity = u.min_porosity;
    diag.particles_outside_mesh = mapping.outside;
  }

  bool frozen_now() const {
    const double t = static_cast<double>(step_index) * step_size;
    return t + 0.5 * step_size <= scene.coupling.freeze_until;
  }

  void step() {
    if (!fluid) {  // dry scene
      const auto t0 = Clock::now();
      dem->set_frozen(frozen_now());
      for (int s = 0; s < subcycles; ++s) dem->step();
      diag.dem_seconds = seconds_since(t0);
      ++step_index;
      return;
    }
    const bool frozen = frozen_now();
    // 1. Fluid step with the source term of the previous step (Fig. 2).
    auto t0 = Clock::now();
    if (!fluid_at_rest) fluid->step(step_size);
    diag.fluid_seconds = seconds_since(t0);

    // 2. Fluid velocity at the particles, frozen over the subcycles (Fig. 4).
    t0 = Clock::now();
    if (drag) drag->begin_step(*mesh, mapping, dem->particles(), fluid->velocity(), porosity->values());
    diag.coupling_seconds = seconds_since(t0);

    // 3. DEM subcycles (Fig. 3), drag evaluated in each.
    t0 = Clock::now();
    dem->set_frozen(frozen);
    for (int s = 0; s < subcycles; ++s) dem->step();
    diag.dem_seconds = seconds_since(t0);
    diag.drag_seconds = drag ? drag->evaluation_seconds() : 0.0;

    // 4. Map again at the new positions, porosity; 5. source term for the next fluid step.
    t0 = Clock::now();
    map_and_porosity();
    diag.drag_on_particles.setZero();
    diag.force_on_fluid.setZero();
    diag.momentum_imbalance = 0.0;
    if (drag) {
      drag->end_step();
      diag.drag_on_particles = drag->total_mean_drag();
    }
    if (source) {
      if (frozen || !drag || drag->mean_drag_x().size() != dem->particles().size()) {
        source->clear();
      } else {
        source->compute(dem->particles(), mapping, porosity->values(), drag->mean_drag_x(), drag->mean_drag_y(),
                        drag->mean_drag_z());
      }
      fluid->set_body_force(source->nodal_force_density());
      diag.force_on_fluid = source->total_force();
      const double drag_norm = diag.drag_on_particles.norm();
      if (drag_norm > 0.0 && !frozen)
        diag.momentum_imbalance = (diag.drag_on_particles + diag.force_on_fluid).norm() / drag_norm;
    }
    diag.coupling_seconds += seconds_since(t0);
    ++step_index;
  }

  // ---- Checkpoint payload: sections "SIM ", "DEM ", and with fluid "FLUI", "COUP"
  // (layout in coupling/checkpoint_format.hpp; field order = the order of the writes).

  bool frozen_at(long step) const {
    const double t = static_cast<double>(step) * step_size;
    return t + 0.5 * step_size <= scene.coupling.freeze_until;
  }

  // Whether the source term now handed to the fluid was built from the mean
  // drag of the last step (else it is zero): the branch of step() 5.
  bool source_from_drag() const {
    if (restored_at_step == step_index) return restored_source_from_drag;
    return source && drag && step_index > 0 && !frozen_at(step_index - 1) &&
           drag->mean_drag_x().size() == dem->particles().size();
  }

  void write_payload(std::ostream& out) const {
    checkpoint::Writer w(out);
    w.section("SIM ", 1);
    w.i64(step_index);
    w.f64(step_size);
    w.i64(subcycles);
    w.boolean(fluid != nullptr);
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
      if (restored_at_step == step_index) {
        for (const auto& v : restored_mean_drag) w.doubles(v);
      } else {
        w.doubles(drag->mean_drag_x());
        w.doubles(drag->mean_drag_y());
        w.doubles(drag->mean_drag_z());
      }
    }
    w.doubles(source ? source->nodal_force_density() : std::span<const double>{});
  }

  // Reads into this (freshly built) Impl; any inconsistency throws.
  void read_payload(std::istream& in) {
    checkpoint::Reader r(in);
    r.section("SIM ", 1);
    const std::int64_t steps = r.i64("the step index");
    const double size = r.f64("the step size");
    const std::int64_t cycles = r.i64("the subcycle count");
    const bool has_fluid = r.boolean("the fluid flag");
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
      if (!bitwise_equal(porosity->values(), saved_porosity))
        throw SolverError("checkpoint: the porosity rebuilt from the particles differs from the saved one "
                          "(another scene or build?)");
      const std::size_t n = dem->particles().size();
      restored_source_from_drag = r.boolean("the source-term flag");
      if (restored_source_from_drag && !(source && drag))
        throw SolverError("checkpoint: a source term from drag, but this scene has no two-way exchange");
      for (auto& v : restored_mean_drag) v.clear();
      if (restored_source_from_drag)
        for (auto& v : restored_mean_drag) v = r.doubles_exactly("the mean drag", n);
      const std::vector<double> saved_source =
          r.doubles("the source term", 3 * static_cast<std::size_t>(mesh->num_nodes()));
      if (source) {
        if (restored_source_from_drag) {
          source->compute(dem->particles(), mapping, porosity->values(), restored_mean_drag[0],
                          restored_mean_drag[1], restored_mean_drag[2]);
        } else {
          source->clear();
        }
        if (!bitwise_equal(source->nodal_force_density(), saved_source))
          throw SolverError("checkpoint: the source term rebuilt from the saved drag differs from the saved one "
                            "(another scene or build?)");
      } else if (!saved_source.empty()) {
        throw SolverError("checkpoint: holds a source term, but this scene sends none to the fluid");
      }
      diag = d;
      restored_at_step = step_index;
    }
    if (in.peek() != std::char_traits<char>::eof())
      throw SolverError("checkpoint: unread data after the last section (another format?)");
  }

  static bool bitwise_equal(std::span<const double> a, std::span<const double> b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
  }
};

Simulation::Simulation(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::step() { impl_->step(); }
double Simulation::time() const { return static_cast<double>(impl_->step_index) * impl_->step_size; }
bool Simulation::finished() const { return impl_->step_index >= impl_->steps_to_end; }
long Simulation::step_index() const { return impl_->step_index; }
long Simulation::steps_to_end() const { return impl_->steps_to_end; }
double Simulation::step_size() const { return impl_->step_size; }
int Simulation::subcycles() const { return impl_->subcycles; }
const Scene& Simulation::scene() const { return impl_->scene; }
const Particles& Simulation::particles() const { return impl_->dem->particles(); }
const BoxMesh* Simulation::mesh() const { return impl_->mesh.get(); }

std::span<const double> Simulation::fluid_velocity() const {
  return impl_->fluid ? impl_->fluid->velocity() : std::span<const double>{};
}
std::span<const double> Simulation::fluid_pressure() const {
  return impl_->fluid ? impl_->fluid->pressure() : std::span<const double>{};
}
std::span<const double> Simulation::porosity() const {
  return impl_->porosity ? impl_->porosity->values() : std::span<const double>{};
}
std::span<const double> Simulation::source_term() const {
  if (impl_->source) return impl_->source->nodal_force_density();
  return impl_->zero_source;
}
std::span<const Index> Simulation::particle_elements() const { return impl_->mapping.element; }

CouplingDiagnostics Simulation::diagnostics() const {
  CouplingDiagnostics d = impl_->diag;
  d.dem = impl_->dem->diagnostics();
  return d;
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
  std::istringstream state(payload, std::ios::in | std::ios::binary);
  next->read_payload(state);
  impl_ = std::move(next);
}

}  // namespace fdem
