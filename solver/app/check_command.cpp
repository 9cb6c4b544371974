#include "app/check_command.hpp"

#include <algorithm>
#include <fstream>
#include <string>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "drag_laws/drag_law.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/fluid_system_size.hpp"
#include "mesh/box_mesh.hpp"
#include "mesh/box_mesh_size.hpp"
#include "scene/particle_csv.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"
#include "scene/scene_schema.hpp"
#include "scene/stability.hpp"
#include "scene/time_steps.hpp"

namespace fdem {

namespace {

std::string mib(double bytes) {
  if (bytes < 1024.0 * 1024.0) return fmt::format("{:.0f} KiB", bytes / 1024.0);
  if (bytes < 1024.0 * 1024.0 * 1024.0) return fmt::format("{:.1f} MiB", bytes / (1024.0 * 1024.0));
  return fmt::format("{:.2f} GiB", bytes / (1024.0 * 1024.0 * 1024.0));
}

// Lightest and heaviest particle the scene can hold: the distributions'
// bounds (the tails matter for the stable step, not only the drawn sample),
// and every row of a csv set.
MassRange scene_mass_range(const Scene& scene) {
  MassRange r;
  r.small_mass_kg = std::numeric_limits<double>::infinity();
  r.large_mass_kg = 0.0;
  auto consider = [&](double d, double rho) {
    const double m = rho * sphere_volume(d);
    if (m < r.small_mass_kg) r = {d, m, r.large_diameter_m, r.large_mass_kg};
    if (m > r.large_mass_kg) {
      r.large_diameter_m = d;
      r.large_mass_kg = m;
    }
  };
  for (const ParticleSet& set : scene.particles) {
    if (set.placement == PlacementKind::csv) {
      for (const auto& rec : read_particle_csv(set.csv_file)) consider(rec.diameter, rec.density);
    } else {
      consider(smallest_diameter(set.size), set.density);
      consider(largest_diameter(set.size), set.density);
    }
  }
  return r;
}

// Neighbour-list entries per particle (full list, each pair twice): centres
// closer than d + skin (skin = d/2, dem/dem_engine.cpp) lie in a sphere of
// 27 particle volumes, so E = 27 x solid fraction of the sets' regions, at
// most the 18 of a touching cubic lattice (6 faces + 12 edges within 1.5 d).
double list_entries_per_particle(const Scene& scene) {
  double solid = 0.0, region = 0.0;
  for (const ParticleSet& set : scene.particles) {
    const double d = 0.5 * (smallest_diameter(set.size) + largest_diameter(set.size));
    const Box box = set.placement == PlacementKind::csv || set.placement == PlacementKind::single ? scene.domain
                                                                                                  : set.region;
    solid += static_cast<double>(count_particles(set)) * sphere_volume(d);
    region += (box.upper - box.lower).prod();
  }
  return region > 0.0 ? std::min(18.0, 27.0 * solid / region) : 0.0;
}

}  // namespace

std::size_t count_particles(const ParticleSet& set) {
  switch (set.placement) {
    case PlacementKind::single: return 1;
    case PlacementKind::lattice:
      return static_cast<std::size_t>(set.lattice[0]) * static_cast<std::size_t>(set.lattice[1]) *
             static_cast<std::size_t>(set.lattice[2]);
    case PlacementKind::random: return static_cast<std::size_t>(set.count);
    case PlacementKind::csv: return read_particle_csv(set.csv_file).size();
  }
  return 0;
}

std::size_t count_particles(const Scene& scene) {
  std::size_t n = 0;
  for (const ParticleSet& set : scene.particles) n += count_particles(set);
  return n;
}

// Peak resident memory of `fdem run`, item by item (bytes per particle, per
// non-zero of the fluid system, per node and element), checked against the
// peak RSS of fdem run on dry, fluid and coupled scenes
// (verification/hard_cases/test_memory_estimate.cpp, nightly).
MemoryEstimate estimate_memory(const Scene& scene, std::size_t particle_count) {
  MemoryEstimate m;
  // Binary, libstdc++, yaml-cpp, the OpenMP runtime and, since the fluid links
  // PETSc, PETSc and Open MPI's shared libraries: measured 32.4 MiB peak RSS for
  // examples/dry_drop.yaml (2026-12-02; 6.2 MiB before PETSc).
  m.process_bytes = 32.0 * 1024 * 1024;
  const auto n = static_cast<double>(particle_count);
  const double entries = list_entries_per_particle(scene);
  // Per particle: x, v, f, diameter, mass (11 doubles), id, body factor;
  // rotation: w, t, inertia (7 doubles); the neighbour list's reference
  // positions (3 doubles), offsets, cell of, cell order, listed (4 ints) and
  // grid (at most 4 cells per particle, 1 int each).
  double per_particle = 11.0 * 8.0 + 4.0 + 8.0 + (scene.effects.rotation ? 7.0 * 8.0 : 0.0) + 3.0 * 8.0 + 4.0 * 4.0 +
                        4.0 * 4.0;
  // Per list entry: the index, and its copy in the per-thread build rows.
  per_particle += entries * 2.0 * 4.0;
  // Tangential slip history: a Vec3 per list entry and per wall (6).
  if (scene.effects.tangential_contact) per_particle += entries * 3.0 * 8.0 + 6.0 * 3.0 * 8.0;
  // Coupling: element index, volume coordinates, fluid velocity, drag impulse.
  if (scene.effects.fluid && scene.effects.coupling != CouplingMode::off) per_particle += 4.0 + 10.0 * 8.0;
  m.particles_bytes = n * per_particle;

  // Output buffers, one at a time (each is built in memory, copied once, and
  // the buffer grows by doubling): about 3 x the file. ASCII VTU ~160 B per
  // particle, ~220 B per fluid node, ~60 B per element; a checkpoint ~100 B
  // per particle, 10 doubles per node, 2 per element.
  double vtu = n * 160.0, checkpoint = n * 100.0;
  if (scene.effects.fluid) {
    const BoxMeshSize mesh = box_mesh_size(scene.cells);
    const auto nodes = static_cast<double>(mesh.nodes), elements = static_cast<double>(mesh.elements);
    const FluidSystemSize system = fluid_system_size(scene.cells, FluidSolverOptions{}.ilut_fill_factor);
    // Per non-zero (8 B value + 4 B column): the system (assembled with the
    // prescribed unknowns eliminated, so at most the full pattern), the
    // ILUT's permuted copy, and the ILUT factors (fill factor x the system,
    // fluid/fluid_system_size.hpp).
    const double matrices = static_cast<double>(system.nonzeros) * (2.0 * 12.0) +
                            static_cast<double>(system.factor_nonzeros) * 12.0;
    // Per node: velocity, three time levels, body force, advecting and history
    // velocities (18 doubles), pressures (3), unknowns and right-hand side (8),
    // BiCGSTAB work vectors (7 x 4); per element: block offsets (16 ints),
    // nodes (4 ints), porosity and its update (3 doubles).
    const double fields = nodes * (18.0 + 3.0 + 8.0 + 28.0) * 8.0 + elements * (16.0 * 4.0 + 4.0 * 4.0 + 3.0 * 8.0);
    m.fluid_bytes = matrices + fields;
    vtu += nodes * 220.0 + elements * 60.0;
    checkpoint += nodes * 10.0 * 8.0 + elements * 2.0 * 8.0;
  }
  m.output_bytes = 3.0 * std::max(scene.output.vtu_interval > 0.0 ? vtu : 0.0,
                                  scene.output.checkpoint_interval > 0.0 ? checkpoint : 0.0);
  return m;
}

double available_memory_bytes() {
  double available = std::numeric_limits<double>::infinity();
  // A cap set by the user (a batch job's share of a node), in MiB.
  if (const char* cap = std::getenv("FDEM_MEMORY_LIMIT_MIB"); cap != nullptr && *cap != '\0')
    available = std::stod(cap) * 1024.0 * 1024.0;
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0.0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") available = std::min(available, kib * 1024.0);
  // A cgroup (v2) limit below the machine's memory binds first.
  std::ifstream limit_file("/sys/fs/cgroup/memory.max"), current_file("/sys/fs/cgroup/memory.current");
  std::string limit;
  double current = 0.0;
  if (limit_file >> limit && limit != "max" && current_file >> current)
    available = std::min(available, std::stod(limit) - current);
  return available;
}

void require_memory_fits(const Scene& scene, bool ignore_limit) {
  const MemoryEstimate estimate = estimate_memory(scene, count_particles(scene));
  const double available = available_memory_bytes();
  if (ignore_limit || estimate.total() <= available) return;
  throw InputError(scene.source_file, "(memory estimate)", mib(estimate.total()),
                   fmt::format("the run would need about {} (particles {}, fluid {}, output buffers {}) but {} is "
                               "available; use fewer cells or particles, or pass --ignore-memory-limit to run anyway",
                               mib(estimate.total()), mib(estimate.particles_bytes), mib(estimate.fluid_bytes),
                               mib(estimate.output_bytes), mib(available)));
}

void print_scene_check(const Scene& scene, const Particles& particles, std::FILE* out) {
  print_scene_check(scene, particles, particles.size(), out);
}

void print_scene_check(const Scene& scene, const Particles& particles, std::size_t particle_count, std::FILE* out) {
  auto line = [&](const std::string& text) { std::fprintf(out, "%s\n", text.c_str()); };
  const Effects& e = scene.effects;
  line(fmt::format("scene      {}{}", scene.source_file, scene.title.empty() ? "" : "  (" + scene.title + ")"));
  line(fmt::format("effects    fluid {}, coupling {}, gravity {}, buoyancy {}, normal contact {}, "
                   "tangential contact {}, rotation {}, walls {}",
                   e.fluid ? "on" : "off", choice_word("effects.coupling", static_cast<std::size_t>(e.coupling)), e.gravity ? "on" : "off", e.buoyancy ? "on" : "off",
                   e.normal_contact ? "on" : "off", e.tangential_contact ? "on" : "off", e.rotation ? "on" : "off",
                   e.walls ? "on" : "off"));
  // A dry scene, or one without exchange, has no drag law to name.
  if (e.fluid && e.coupling != CouplingMode::off) {
    const DragLawEntry& law = drag_law(e.drag);
    line(fmt::format("drag       {}: {}; exchange {}", law.name, law.doc,
                     choice_word("coupling.exchange", static_cast<std::size_t>(scene.coupling.exchange))));
  }
  const Vec3 length = scene.domain.upper - scene.domain.lower;
  line(fmt::format("domain     {:g} x {:g} x {:g} m", length.x(), length.y(), length.z()));

  Vec3 cell_size = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  if (e.fluid) {
    const double cells = static_cast<double>(scene.cells[0]) * scene.cells[1] * scene.cells[2];
    cell_size = Vec3(length.x() / scene.cells[0], length.y() / scene.cells[1], length.z() / scene.cells[2]);
    line(fmt::format("mesh       {} x {} x {} cells = {:.0f} cells, {:.0f} elements (tetrahedra), {} nodes; cell "
                     "{:g} x {:g} x {:g} m",
                     scene.cells[0], scene.cells[1], scene.cells[2], cells, 5.0 * cells,
                     static_cast<long long>(scene.cells[0] + 1) * (scene.cells[1] + 1) * (scene.cells[2] + 1),
                     cell_size.x(), cell_size.y(), cell_size.z()));
  } else {
    line("mesh       none (effects.fluid: false)");
  }

  const std::size_t n = particle_count;
  double d_min = 0.0, d_max = 0.0, d_mean = 0.0;
  if (n > 0 && particles.size() != n) {
    // Not drawn (too many to be cheap): the distributions' bounds stand in.
    d_min = std::numeric_limits<double>::infinity();
    for (const ParticleSet& set : scene.particles) {
      if (set.placement == PlacementKind::csv) continue;
      d_min = std::min(d_min, smallest_diameter(set.size));
      d_max = std::max(d_max, largest_diameter(set.size));
    }
    d_mean = 0.5 * (d_min + d_max);
    line(fmt::format("particles  {} in {} set(s), not drawn by check (more than {}); diameter bounds [{:.4g}, {:.4g}] m",
                     n, scene.particles.size(), kMostParticlesDrawnByCheck, d_min, d_max));
  } else if (n > 0) {
    const auto [lo, hi] = std::minmax_element(particles.diameter.begin(), particles.diameter.end());
    d_min = *lo;
    d_max = *hi;
    for (double d : particles.diameter) d_mean += d;
    d_mean /= static_cast<double>(n);
    double solid = 0.0;
    for (double d : particles.diameter) solid += sphere_volume(d);
    line(fmt::format("particles  {} in {} set(s); diameter min {:.4g} m, max {:.4g} m, mean {:.4g} m; solid fraction "
                     "of the domain {:.3g}",
                     n, scene.particles.size(), d_min, d_max, d_mean, solid / length.prod()));
    for (const ParticleSet& set : scene.particles) {
      if (set.placement == PlacementKind::csv) continue;
      line(fmt::format("           set '{}': diameter bounds [{:.4g}, {:.4g}] m", set.name, smallest_diameter(set.size),
                       largest_diameter(set.size)));
    }
  } else {
    line("particles  none");
  }

  const TimeSpec& t = scene.time;
  const double steps = std::round(t.end_time / t.fluid_step);
  if (e.fluid) {
    line(fmt::format("time       fluid step {:g} s, {:.0f} fluid steps to {:g} s", t.fluid_step, steps, t.end_time));
  } else {
    line(fmt::format("time       driver step {:g} s, {:.0f} steps to {:g} s", t.fluid_step, steps, t.end_time));
  }
  std::optional<MassRange> stability_masses;  // an unstable step is refused after everything is printed
  if (n > 0) {
    line(fmt::format("subcycles  {} DEM steps of {:g} s per fluid step, {:.0f} DEM steps in all", t.subcycles,
                     t.dem_step, steps * t.subcycles));
    if (e.normal_contact) {
      const MassRange range = scene_mass_range(scene);
      const StabilityReport report = analyse_stability(scene.contact, e, range, t.dem_step, e.walls);
      line(fmt::format("contacts   ({}; stable step = 0.5 x the explicit limit, scene/stability.hpp)",
                       contact_law_entry(scene.contact.law).summary));
      std::string table = report.table();
      if (!table.empty() && table.back() == '\n') table.pop_back();
      std::fprintf(out, "%s\n", table.c_str());
      line(fmt::format("dt ratio   dem_step / stable bound = {:.3g}{}", t.dem_step / report.stable_step_s(),
                       report.stable() ? "" : (scene.contact.allow_unstable_step ? "  (UNSTABLE, allowed by contact.allow_unstable_step)" : "  (UNSTABLE)")));
      stability_masses = range;
    } else {
      line("contacts   none (effects.normal_contact: false)");
    }
    if (e.fluid) {
      const double h_min = cell_size.minCoeff();
      line(fmt::format("cell/d     min cell size / max diameter = {:.3g}, / mean diameter = {:.3g}{}", h_min / d_max,
                       h_min / d_mean,
                       h_min / d_max < 3.0 ? "  (below 3: element porosity may reach the floor)" : ""));
    }
  }
  const MemoryEstimate mem = estimate_memory(scene, n);
  line(fmt::format("memory     about {} peak (particles {}, fluid {}, output buffers {}, process {}); available {}",
                   mib(mem.total()), mib(mem.particles_bytes), mib(mem.fluid_bytes), mib(mem.output_bytes),
                   mib(mem.process_bytes), mib(available_memory_bytes())));
  line(fmt::format("output     {}: VTU every {}, CSV every {}, checkpoint every {}", scene.output.directory,
                   scene.output.vtu_interval > 0 ? fmt::format("{:g} s", scene.output.vtu_interval) : "(never)",
                   scene.output.csv_interval > 0 ? fmt::format("{:g} s", scene.output.csv_interval) : "step",
                   scene.output.checkpoint_interval > 0 ? fmt::format("{:g} s", scene.output.checkpoint_interval)
                                                        : "(never)"));
  std::fflush(out);
  if (stability_masses) require_stable_dem_step(scene, *stability_masses, t.dem_step);
}

void require_runnable_size(const Scene& scene) {
  if (scene.effects.fluid)
    require_indexable_fluid_system(scene.cells, FluidSolverOptions{}.ilut_fill_factor, scene.source_file);
}

int run_check_command(const std::string& scene_path, std::FILE* out, bool ignore_memory_limit) {
  const Scene scene = load_scene(scene_path);
  require_runnable_size(scene);
  const std::size_t count = count_particles(scene);
  const Particles particles = count <= kMostParticlesDrawnByCheck ? generate_particles(scene) : Particles{};
  print_scene_check(scene, particles, count, out);
  require_memory_fits(scene, ignore_memory_limit);
  std::fprintf(out, "ok         %s is valid\n", scene_path.c_str());
  return 0;
}

}  // namespace fdem
