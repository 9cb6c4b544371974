#include "channel_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "coupling/simulation.hpp"
#include "dem/dem_engine.hpp"
#include "io/atomic_file.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem::channel {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

Scene base_scene() { return load_scene(std::string(FDEM_SOURCE_DIR) + "/verification/channel/channel.yaml"); }

double damping_for_stiffness(double stiffness_n_m) {
  return kPaperDamping_N_s_m * std::sqrt(stiffness_n_m / kPaperStiffness_N_m);
}

Scene paper_contact_scene() {
  Scene s = base_scene();
  s.contact.normal_stiffness = kPaperStiffness_N_m;
  s.contact.normal_damping = kPaperDamping_N_s_m;
  s.contact.restitution.reset();
  s.time.dem_step = kPaperDemStep_s;
  s.time.fluid_step = 5.0e-3;  // Table 3
  s.time.subcycles = 0;
  return s;
}

BedStats settle_bed(const Scene& base, double settle_time_s, const std::string& csv_path) {
  const auto t0 = Clock::now();
  Scene dry = base;
  dry.effects.fluid = false;
  dry.effects.coupling = CouplingMode::off;
  dry.effects.buoyancy = false;  // no fluid: the bed's geometry, not its weight in water, is what we keep
  dry.time.fluid_step = 0.0;
  dry.time.subcycles = 0;
  DemEngine dem(generate_particles(dry), dry);
  dem.run(static_cast<std::size_t>(std::lround(settle_time_s / dry.time.dem_step)));
  const DemDiagnostics d = dem.diagnostics();
  const Particles& p = dem.particles();
  BedStats s;
  s.max_overlap_over_diameter = d.max_overlap_over_diameter;
  s.kinetic_energy_j = d.kinetic_energy_j;
  s.contacts = d.contacts;
  s.particles = p.size();
  s.settle_time_s = dem.time();
  std::string csv = "id,d,rho,x,y,z\n";  // the anchors' format (scene/particle_csv.hpp), no comment lines
  const double density = base.particles.at(0).density;
  for (std::size_t i = 0; i < p.size(); ++i) {
    s.top_m = std::max(s.top_m, p.z[i] + 0.5 * p.diameter[i]);
    csv += fmt::format("{},{},{},{},{},{}\n", i + 1, p.diameter[i], density, p.x[i], p.y[i], p.z[i]);
  }
  write_file_atomically(csv_path, csv);
  s.wall_time_s = since(t0);
  return s;
}

Scene wall_case(const Scene& base, double end_time_s) {
  Scene s = base;
  s.particles.clear();
  s.effects.coupling = CouplingMode::off;
  // Every node above the bottom wall.
  s.fluid.faces[static_cast<std::size_t>(BoxFace::x_min)].inlet_above_m = s.domain.lower.z();
  s.time.end_time = end_time_s;
  return s;
}

Scene bed_case(const Scene& base, double end_time_s, const std::string& bed_csv, double bed_top_m) {
  Scene s = base;
  s.particles.at(0).placement = PlacementKind::csv;
  s.particles.at(0).csv_file = bed_csv;
  s.fluid.faces[static_cast<std::size_t>(BoxFace::x_min)].inlet_above_m = bed_top_m;  // 0 at and below the bed
  s.time.end_time = end_time_s;
  return s;
}

Profile outlet_profile(const Simulation& sim) {
  const BoxMesh& mesh = *sim.mesh();
  const auto [nx, ny, nz] = mesh.cells();
  const std::span<const double> u = sim.fluid_velocity();
  Profile p;
  for (int k = 0; k <= nz; ++k) {
    double sum = 0.0;
    for (int j = 0; j <= ny; ++j) sum += u[3 * static_cast<std::size_t>(mesh.node_index(nx, j, k))];
    p.z_m.push_back(mesh.node(mesh.node_index(nx, 0, k)).z() - mesh.lower().z());
    p.u_mps.push_back(sum / (ny + 1));
  }
  return p;
}

Slope near_bed_slope(const Profile& profile, double z_from_m, double band_m) {
  // Least squares of u on z over the nodes in the band (tolerance: a node on
  // the band's edge counts despite round-off in its coordinate).
  const double eps = 1e-9;
  double sz = 0, su = 0, szz = 0, szu = 0;
  int n = 0;
  double first = INFINITY, last = -INFINITY;
  for (std::size_t i = 0; i < profile.z_m.size(); ++i) {
    const double z = profile.z_m[i];
    if (z < z_from_m - eps || z > z_from_m + band_m + eps) continue;
    sz += z;
    su += profile.u_mps[i];
    szz += z * z;
    szu += z * profile.u_mps[i];
    first = std::min(first, z);
    last = std::max(last, z);
    ++n;
  }
  if (n < 2) throw std::invalid_argument(fmt::format("near_bed_slope: fewer than 2 nodes in [{}, {}] m", z_from_m,
                                                     z_from_m + band_m));
  Slope s;
  s.dudz_1ps = (n * szu - sz * su) / (n * szz - sz * sz);
  s.z_from_m = first;
  s.z_to_m = last;
  s.u_at_z_from_mps = (su - s.dudz_1ps * sz) / n + s.dudz_1ps * first;
  s.slope_deg = std::atan(1.0 / s.dudz_1ps) * 180.0 / std::numbers::pi;
  return s;
}

CaseRun run_case(const Scene& scene, double z_probe_m) {
  const auto t0 = Clock::now();
  Simulation sim(scene);
  CaseRun r;
  const long probe_every = std::max(1L, std::lround(0.05 / sim.step_size()));
  while (!sim.finished()) {
    sim.step();
    const CouplingDiagnostics d = sim.diagnostics();
    r.floored_element_updates = d.floored_element_updates;
    r.floored_elements_last = d.floored_elements;
    r.min_porosity = std::min(r.min_porosity, d.min_porosity);
    r.max_overlap_over_diameter = std::max(r.max_overlap_over_diameter, d.dem.max_overlap_over_diameter);
    r.particles_removed = d.dem.particles_removed;
    r.max_momentum_imbalance = std::max(r.max_momentum_imbalance, d.momentum_imbalance);
    if (sim.step_index() % probe_every == 0) {
      const Profile p = outlet_profile(sim);
      std::size_t k = 0;
      while (k + 1 < p.z_m.size() && p.z_m[k] < z_probe_m - 1e-9) ++k;
      r.t_s.push_back(sim.time());
      r.u_probe_mps.push_back(p.u_mps[k]);
    }
  }
  r.profile = outlet_profile(sim);
  r.wall_time_s = since(t0);
  return r;
}

StepProbe probe_fluid_step(const Scene& bed_scene, double fluid_step_s, MomentumExchange exchange,
                           double coupled_time_s) {
  const auto t0 = Clock::now();
  Scene s = bed_scene;
  s.coupling.exchange = exchange;
  s.coupling.freeze_until = 0.0;
  s.time.fluid_step = fluid_step_s;
  s.time.subcycles = 0;
  s.time.end_time = std::max(coupled_time_s, 5.0 * fluid_step_s);
  StepProbe p;
  p.fluid_step_s = fluid_step_s;
  try {
    Simulation sim(s);
    while (!sim.finished()) {
      sim.step();
      ++p.steps;
      const std::span<const double> u = sim.fluid_velocity();
      for (std::size_t a = 0; a + 2 < u.size(); a += 3)
        p.max_speed_m_s = std::max(p.max_speed_m_s, std::sqrt(u[a] * u[a] + u[a + 1] * u[a + 1] + u[a + 2] * u[a + 2]));
      if (!(p.max_speed_m_s <= kUnstableSpeed_m_s)) {  // also NaN
        p.failure = "speed";
        break;
      }
      if (sim.diagnostics().dem.particles_removed > 0) {
        p.failure = "grains lost";
        break;
      }
    }
  } catch (const std::exception& e) {
    p.failure = e.what();
  }
  p.stable = p.failure.empty();
  p.wall_time_s = since(t0);
  return p;
}

StableStep largest_stable_fluid_step(const Scene& bed_scene, MomentumExchange exchange, double lo_s, double hi_s,
                                     int bisections, double coupled_time_s) {
  const double dem = bed_scene.time.dem_step;
  const auto whole = [dem](double dt) { return std::max(1.0, std::round(dt / dem)) * dem; };
  StableStep r;
  const auto probe = [&](double dt) {
    r.probes.push_back(probe_fluid_step(bed_scene, dt, exchange, coupled_time_s));
    return r.probes.back().stable;
  };
  double lo = whole(lo_s), hi = whole(hi_s);
  if (!probe(lo)) {
    r.smallest_unstable_s = lo;
    return r;
  }
  if (probe(hi)) {
    r.largest_stable_s = hi;
    return r;
  }
  for (int k = 0; k < bisections; ++k) {
    const double mid = whole(std::sqrt(lo * hi));
    if (mid <= lo || mid >= hi) break;  // one DEM step apart
    (probe(mid) ? lo : hi) = mid;
  }
  r.largest_stable_s = lo;
  r.smallest_unstable_s = hi;
  return r;
}

ExplicitBound explicit_step_bound(const Scene& bed_scene) {
  Scene s = bed_scene;
  s.coupling.exchange = MomentumExchange::semi_implicit;
  s.coupling.freeze_until = 0.0;
  const Simulation sim(s);  // the exchange's coefficients of the bed at rest, fluid at rest
  const std::span<const double> all = sim.momentum_exchange_beta();
  std::vector<double> beta;
  for (double b : all)
    if (b > 0.0) beta.push_back(b);
  ExplicitBound b;
  if (beta.empty()) return b;
  std::sort(beta.begin(), beta.end());
  b.beta_max = beta.back();
  b.beta_median = beta[beta.size() / 2];
  b.step_s = 4.0 * s.fluid.density / b.beta_max;
  return b;
}

}  // namespace fdem::channel
