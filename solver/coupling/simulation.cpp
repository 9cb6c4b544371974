// The coupled step (paper Sect. 2.3, Fig. 2-4): what the scene needs is
// built once, then each step() runs the flowchart. The checkpoint payload
// is simulation_state.cpp's.
#include "coupling/simulation.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/petsc_runtime.hpp"
#include "fluid/petsc_linear_solver.hpp"
#include "coupling/coupled_step_bounds.hpp"
#include "coupling/simulation_impl.hpp"
#include "parallel/grain_exchange.hpp"
#include "scene/particle_generator.hpp"
#include "scene/stability.hpp"
#include "scene/time_steps.hpp"

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

// The scene with its time steps resolved by the one rule set
// (scene/time_steps.hpp), for scenes loaded from a file (already resolved:
// nothing changes) and scenes built in code alike.
Scene with_resolved_time_steps(const Scene& in, const Particles& particles) {
  Scene out = in;
  std::optional<MassRange> masses;
  if (particles.size() > 0) masses = mass_range(particles);
  out.time = resolve_time_steps(in, masses, [&in](const std::string& key, const std::string& reason) {
    const TimeSpec& t = in.time;
    const std::string value = key == "subcycles" ? std::to_string(t.subcycles)
                                                 : fmt::format("{:g}", key == "dem_step" ? t.dem_step : t.fluid_step);
    throw InputError(in.source_file, "time." + key, value, reason);
  });
  return out;
}

// On several MPI ranks the grains are decomposed in slabs along the box's
// longest axis (parallel/grain_exchange.hpp). A coupled scene's per-grain
// drag state travels with its grains (DragCoupling::carried_state), and its
// sums over grains into the replicated mesh's fields are over each rank's
// owned grains, added over the ranks (parallel/grain_share.hpp); the slip
// history of tangential contact travels with the grains too (DemEngine::
// decompose). Returns why not, or "" when decomposed; `grains` the
// exchange (owned by `dem`) or nullptr.
std::string decompose_over_ranks(DemEngine& dem, const Scene& s, GrainExchange*& grains) {
  grains = nullptr;
  const int ranks = mpi_ranks();
  if (ranks < 2) return "one rank";
  const Vec3 extent = s.domain.upper - s.domain.lower;
  if (!(extent.minCoeff() > 0.0)) return "no domain box to cut in slabs";
  try {
    auto exchange = std::make_unique<GrainExchange>(SlabPartition(s.domain.lower, s.domain.upper, ranks),
                                                    s.effects.rotation);
    GrainExchange* const held = exchange.get();
    // A fluid's coupling sums grains into elements by slab bands: owners stay in their slabs.
    dem.decompose(std::move(exchange), s.effects.fluid);
    grains = held;
  } catch (const std::invalid_argument& e) {
    return e.what();  // slabs thinner than the ghost cutoff: the same on every rank
  }
  return "";
}

}  // namespace

Simulation::Impl::Impl(const Scene& s) {
  if (find_drag_law(s.effects.drag) == nullptr)  // a scene built in code: the loader checks its own
    throw InputError(s.source_file, "effects.drag", s.effects.drag, "expected one of: " + drag_law_names());
  Particles particles = generate_particles(s);
  scene = with_resolved_time_steps(s, particles);
  step_size = scene.time.fluid_step;
  subcycles = scene.time.subcycles;
  steps_to_end = std::lround(std::ceil(scene.time.end_time / step_size - 1e-9));
  fingerprint = checkpoint::scene_fingerprint(scene, subcycles, particles);
  dem.emplace(std::move(particles), scene);
  diag.subcycles = subcycles;
  replicated_because = decompose_over_ranks(*dem, scene, grains);

  if (!scene.effects.fluid) return;  // dry scene: no mesh, no fluid, no coupling state
  mesh = std::make_unique<BoxMesh>(scene.domain.lower, scene.domain.upper, scene.cells);
  FluidSolverOptions fluid_options;
  fluid_options.report_divergence = false;  // the step's report is not read here
  fluid = std::make_unique<FluidSolver>(*mesh, scene, fluid_options);
  fluid_at_rest = fluid_stays_at_rest(scene);
  if (grains != nullptr) {
    // The rows each rank's fluid assembles, as fluid/fluid_solver.cpp splits them.
    std::vector<std::pair<Index, Index>> rows;
    for (int r = 0; r < grains->ranks(); ++r)
      rows.push_back(PetscLinearSolver::owned_node_range(mesh->num_nodes(), r, grains->ranks()));
    element_sums = std::make_unique<ElementSums>(MeshCells{mesh->cells(), mesh->lower(), mesh->cell_size()},
                                                 std::move(rows), *grains);
  }
  porosity = std::make_unique<PorosityField>(*mesh, scene.coupling, dem->particles());
  const CouplingMode mode = scene.effects.coupling;
  // The semi-implicit exchange needs a fluid that takes the drag; with
  // fluid_to_particle the grains alone feel it, evaluated every subcycle.
  const bool semi_implicit =
      source_on_fluid(mode) && momentum_exchange_entry(scene.coupling.exchange).coefficient_in_fluid_matrix;
  if (mode != CouplingMode::off) {
    drag = std::make_unique<DragCoupling>(drag_law(scene.effects.drag),
                                          FluidProperties{scene.fluid.density, scene.fluid.viscosity},
                                          drag_on_particles(mode), semi_implicit, grain_drag_form(scene.fluid.model));
    dem->set_external_force(drag.get());
    if (scene.fluid.model == FluidModel::vans_a && drag_on_particles(mode)) {
      fluid_stress = std::make_unique<FluidStressForce>(drag.get());
      dem->set_external_force(fluid_stress.get());
    }
  }
  if (semi_implicit) {
    exchange = std::make_unique<SemiImplicitExchange>(*mesh, fluid_source_form(scene));
  } else if (source_on_fluid(mode)) {
    source = std::make_unique<SourceTerm>(*mesh, fluid_source_form(scene));
  }
  if (!source) zero_source.assign(3 * static_cast<std::size_t>(mesh->num_nodes()), 0.0);
  map_and_porosity();
  if (exchange) prepare_exchange();
}

// Fig. 4: particle mapping, then porosity per element.
// Decomposed over MPI ranks, this rank's grains and ghosts are mapped, and
// its owned grains counted (share()).
void Simulation::Impl::map_and_porosity() {
  mapping.update(*mesh, dem->particles());
  const GrainShare owned = share();
  const PorosityUpdate u = porosity->update(dem->particles(), mapping, owned);
  long floored = u.floored_elements;
  double least = u.min_porosity;
  if (element_sums) {  // each element counted by its owner
    double count = static_cast<double>(floored);
    owned.sum_over_element_owners(std::span<double>(&count, 1));
    floored = std::lround(count);
    least = -owned.max_over_element_owners(-least);
  }
  diag.floored_elements = floored;
  diag.floored_element_updates += floored;
  diag.min_porosity = least;
  diag.particles_outside_mesh = mapping.outside;
  if (owned.decomposed()) {
    long outside = 0;
    for (std::size_t i = 0; i < mapping.element.size(); ++i)
      if (mapping.element[i] < 0 && owned.counts(i)) ++outside;
    diag.particles_outside_mesh = std::lround(owned.sum_over_ranks(static_cast<double>(outside)));
  }
  fluid->set_porosity(porosity->values());  // eps at the next fluid step's new level (Eq. 18-19)
}

// A failed fluid solve or DEM blow-up inside a coupled step: name the step at
// fault (fluid or DEM, coupling/coupled_step_bounds.hpp). The DEM's own
// message blames its step; that clause is dropped when the bounds blame another.
std::string Simulation::Impl::blow_up_message(std::string dem_message) const {
  const CoupledStepBounds bounds = assess_coupled_step(scene, *mesh, dem->particles(), mapping, porosity->values(),
                                                       fluid->velocity(), step_size, scene.time.dem_step);
  const bool contacts_at_fault =
      bounds.contact_ratio > 1.0 && bounds.contact_ratio >= std::max(bounds.exchange_ratio, bounds.drag_ratio);
  const std::size_t clause = dem_message.find("; the DEM step");
  if (!contacts_at_fault && clause != std::string::npos) dem_message.erase(clause);
  return fmt::format("fluid step {}: {}; cause: {}", step_index + 1, dem_message, bounds.cause());
}

void Simulation::Impl::prepare_exchange() {
  drag->freeze_coefficients(*mesh, mapping, dem->particles(), fluid->velocity(), porosity->values());
  if (frozen_at(step_index)) {
    exchange->clear();
  } else {
    exchange->compute(dem->particles(), mapping, drag->frozen_coefficients(), porosity->values(), share());
  }
  fluid->set_momentum_exchange(exchange->element_beta(), exchange->element_particle_velocity());
}

void Simulation::Impl::step() {
  if (!fluid) {  // dry scene
    const auto t0 = Clock::now();
    dem->set_frozen(frozen_at(step_index));
    const std::size_t dem_steps_before = dem->steps();
    for (int s = 0; s < subcycles; ++s) dem->step();
    if (dem->sort_due(dem_steps_before)) dem->sort_in_cell_order();
    collect();  // decomposed: the summed diagnostics (and the whole set) on every rank
    diag.dem_seconds = seconds_since(t0);
    ++step_index;
    return;
  }
  const bool frozen = frozen_at(step_index);
  // 1. Fluid step with the source term of the previous step (Fig. 2), or
  //    with the semi-implicit exchange's beta_e, v_e taken at its end.
  auto t0 = Clock::now();
  try {
    if (!fluid_at_rest) fluid->step(step_size);
  } catch (const SolverError& e) {
    throw SolverError(blow_up_message(e.what()));
  }
  diag.fluid_seconds = seconds_since(t0);
  // What the semi-implicit exchange gave the fluid in this solve: beta_e (v_e - u^{n+1}).
  const Vec3 exchanged = exchange ? exchange->force_on_fluid(fluid->velocity(), share()) : Vec3::Zero();

  // 2. Fluid velocity at the particles, frozen over the subcycles (Fig. 4).
  t0 = Clock::now();
  if (drag) drag->begin_step(*mesh, mapping, dem->particles(), fluid->velocity(), porosity->values());
  if (fluid_stress) fluid_stress->begin_step(mapping, dem->particles(), *fluid, *porosity);
  diag.coupling_seconds = seconds_since(t0);

  // 3. DEM subcycles (Fig. 3), drag evaluated in each.
  t0 = Clock::now();
  dem->set_frozen(frozen);
  const std::size_t dem_steps_before = dem->steps();
  try {
    for (int s = 0; s < subcycles; ++s) dem->step();
  } catch (const SolverError& e) {
    throw SolverError(blow_up_message(e.what()));
  }
  if (drag) drag->end_step();
  // The grains in memory order now and then (DemEngine::sort_in_cell_order):
  // here, where the only per-grain coupling state still needed is the mean
  // drag, and before the mapping and porosity, which are then built in the
  // new order (so a checkpoint written after this step rebuilds them bit
  // for bit).
  if (dem->sort_due(dem_steps_before)) {
    const std::span<const Index> order = dem->sort_in_cell_order();
    if (drag && !order.empty()) drag->reorder(order);
  }
  diag.dem_seconds = seconds_since(t0);
  diag.drag_seconds = drag ? drag->evaluation_seconds() : 0.0;

  // 4. Map again at the new positions, porosity; 5. source term for the next fluid step.
  t0 = Clock::now();
  map_and_porosity();
  diag.drag_on_particles.setZero();
  diag.force_on_fluid.setZero();
  diag.momentum_imbalance = 0.0;
  if (drag) diag.drag_on_particles = drag->total_mean_drag(share());
  if (exchange) {
    diag.force_on_fluid = exchanged;
  } else if (source) {
    if (builds_source_from_drag(frozen)) {
      source->compute(dem->particles(), mapping, porosity->values(), drag->mean_drag_x(), drag->mean_drag_y(),
                      drag->mean_drag_z(), share());
    } else {
      source->clear();
    }
    fluid->set_body_force(source->nodal_force_density());
    diag.force_on_fluid = source->total_force();
  }
  const double drag_norm = diag.drag_on_particles.norm();
  if ((exchange || source) && drag_norm > 0.0 && !frozen)
    diag.momentum_imbalance = (diag.drag_on_particles + diag.force_on_fluid).norm() / drag_norm;
  ++step_index;
  if (exchange) prepare_exchange();  // for the next step, whose freeze state decides
  collect();  // decomposed: the summed diagnostics (and the whole set) on every rank
  diag.coupling_seconds += seconds_since(t0);
}

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
const Particles& Simulation::particles() const { return impl_->dem->whole_particles(); }
const Particles& Simulation::local_particles() const { return impl_->dem->particles(); }
void Simulation::set_gather_each_step(bool on) { impl_->gather_each_step = on; }
void Simulation::gather_particles() {
  if (!impl_->dem->whole_particles_current()) impl_->dem->collect();
}
const GrainExchange* Simulation::grain_exchange() const { return impl_->dem->exchange(); }
const ElementSums* Simulation::element_sums() const { return impl_->element_sums.get(); }
const std::string& Simulation::replicated_because() const { return impl_->replicated_because; }
const BoxMesh* Simulation::mesh() const { return impl_->mesh.get(); }
void Simulation::set_grain_sort_policy(DemEngine::GrainSortPolicy policy) { impl_->dem->set_grain_sort_policy(policy); }

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
std::vector<double> Simulation::porosity_for_output() const {
  const Impl& m = *impl_;
  if (!m.porosity) return {};
  if (m.element_sums) return m.element_sums->gather_elements(m.porosity->values(), 1);
  return {m.porosity->values().begin(), m.porosity->values().end()};
}
std::vector<double> Simulation::source_term_for_output() const {
  const Impl& m = *impl_;
  const std::span<const double> mine = source_term();
  if (m.element_sums && m.mesh) return m.element_sums->gather_nodes(mine, 3);
  return {mine.begin(), mine.end()};
}
std::span<const double> Simulation::momentum_exchange_beta() const {
  return impl_->exchange ? impl_->exchange->element_beta() : std::span<const double>{};
}
std::span<const Index> Simulation::particle_elements() const { return impl_->mapping.element; }

void Simulation::set_inlet_velocity(BoxFace face, const Vec3& velocity_m_s) {
  Impl& m = *impl_;
  if (!m.fluid) throw SolverError("set_inlet_velocity: the scene has no fluid");
  m.fluid->set_inlet_velocity(face, velocity_m_s);  // refuses a face that is not an inlet
  m.scene.fluid.faces[static_cast<std::size_t>(face)].velocity = velocity_m_s;
  m.fluid_at_rest = fluid_stays_at_rest(m.scene);
}

CouplingDiagnostics Simulation::diagnostics() const {
  CouplingDiagnostics d = impl_->diag;
  d.dem = impl_->dem->diagnostics();
  return d;
}
CouplingDiagnostics Simulation::coupling_diagnostics() const { return impl_->diag; }

}  // namespace fdem
