#include "app/check_command.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "dem/stability.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/fluid_system_size.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/particle_csv.hpp"
#include "scene/particle_generator.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {

namespace {

const char* name_of(CouplingMode m) {
  switch (m) {
    case CouplingMode::off: return "off";
    case CouplingMode::fluid_to_particle: return "fluid_to_particle";
    case CouplingMode::particle_to_fluid: return "particle_to_fluid";
    case CouplingMode::two_way: return "two_way";
  }
  return "?";
}

std::string mib(double bytes) {
  if (bytes < 1024.0 * 1024.0) return fmt::format("{:.0f} KiB", bytes / 1024.0);
  return fmt::format("{:.1f} MiB", bytes / (1024.0 * 1024.0));
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

}  // namespace

MemoryEstimate estimate_memory(const Scene& scene, std::size_t particle_count) {
  MemoryEstimate m;
  const auto n = static_cast<double>(particle_count);
  // Per particle: x, v, f (9), diameter, mass (2) doubles; rotation adds w, t, I (7).
  double per_particle = 11.0 * 8.0 + (scene.effects.rotation ? 7.0 * 8.0 : 0.0);
  // Verlet neighbour list: ~13 partners per particle in a dense pack (half of
  // ~26), 4-byte index each, plus the cell-list binning (two indices).
  per_particle += 13.0 * 4.0 + 2.0 * 4.0;
  // Tangential slip history: 3 doubles + the partner index per contact.
  if (scene.effects.tangential_contact) per_particle += 6.0 * (3.0 * 8.0 + 4.0);
  // Coupling: element index, interpolated fluid velocity, drag impulse.
  if (scene.effects.coupling != CouplingMode::off) per_particle += 4.0 + 6.0 * 8.0;
  m.particles_bytes = n * per_particle;
  if (!scene.effects.fluid) return m;

  const double cells = static_cast<double>(scene.cells[0]) * scene.cells[1] * scene.cells[2];
  const double nodes = static_cast<double>(scene.cells[0] + 1) * (scene.cells[1] + 1) * (scene.cells[2] + 1);
  const double elements = 5.0 * cells;
  // Edges of the 5-tet split: the 3 axis directions (~3 per node) plus one
  // face diagonal per cell face (~3 per cell) and none across the body: ~3 n + 3 c.
  const double edges = 3.0 * nodes + 3.0 * cells;
  const double dofs = 4.0 * nodes;  // u, v, w, p per node (P1-P1 stabilised)
  // Block sparse system: (diagonal + both directions of each edge) 4x4 blocks,
  // value (8 B) + column index (4 B) per entry.
  const double nonzeros = 16.0 * (nodes + 2.0 * edges);
  const double matrix = nonzeros * 12.0 + dofs * 4.0;
  // Preconditioner (ILU(0)-sized copy) and ~10 Krylov / history vectors.
  const double solver = matrix + 10.0 * dofs * 8.0;
  // Mesh connectivity (4 indices per element) and element fields (porosity, volume).
  const double mesh = elements * (4.0 * 4.0 + 2.0 * 8.0) + nodes * 3.0 * 8.0;
  // Nodal fields: velocity (3 time levels), pressure, source term.
  const double fields = nodes * (3.0 * 3.0 + 1.0 + 3.0) * 8.0;
  m.fluid_bytes = matrix + solver + mesh + fields;
  return m;
}

void print_scene_check(const Scene& scene, const Particles& particles, std::FILE* out) {
  auto line = [&](const std::string& text) { std::fprintf(out, "%s\n", text.c_str()); };
  const Effects& e = scene.effects;
  line(fmt::format("scene      {}{}", scene.source_file, scene.title.empty() ? "" : "  (" + scene.title + ")"));
  line(fmt::format("effects    fluid {}, coupling {}, gravity {}, buoyancy {}, drag {}, normal contact {}, "
                   "tangential contact {}, rotation {}, walls {}",
                   e.fluid ? "on" : "off", name_of(e.coupling), e.gravity ? "on" : "off", e.buoyancy ? "on" : "off",
                   e.drag == DragLaw::stokes ? "stokes" : "ergun_wen_yu", e.normal_contact ? "on" : "off",
                   e.tangential_contact ? "on" : "off", e.rotation ? "on" : "off", e.walls ? "on" : "off"));
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

  const std::size_t n = particles.size();
  double d_min = 0.0, d_max = 0.0, d_mean = 0.0;
  if (n > 0) {
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
  std::optional<StabilityReport> stability;  // refused, if unstable, after everything is printed
  if (n > 0) {
    line(fmt::format("subcycles  {} DEM steps of {:g} s per fluid step, {:.0f} DEM steps in all", t.subcycles,
                     t.dem_step, steps * t.subcycles));
    if (e.normal_contact) {
      const MassRange range = scene_mass_range(scene);
      const StabilityReport report = analyse_stability(scene.contact, e, range, t.dem_step, e.walls);
      line("contacts   (linear spring-dashpot, Eq. 6-7; stable step = 0.5 x the explicit limit, dem/stability.hpp)");
      std::string table = report.table();
      if (!table.empty() && table.back() == '\n') table.pop_back();
      std::fprintf(out, "%s\n", table.c_str());
      line(fmt::format("dt ratio   dem_step / stable bound = {:.3g}{}", t.dem_step / report.stable_step_s(),
                       report.stable() ? "" : (scene.contact.allow_unstable_step ? "  (UNSTABLE, allowed by contact.allow_unstable_step)" : "  (UNSTABLE)")));
      stability = report;
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
  line(fmt::format("memory     about {} (particles {}, fluid {}; rough estimate)", mib(mem.total()),
                   mib(mem.particles_bytes), mib(mem.fluid_bytes)));
  line(fmt::format("output     {}: VTU every {}, CSV every {}, checkpoint every {}", scene.output.directory,
                   scene.output.vtu_interval > 0 ? fmt::format("{:g} s", scene.output.vtu_interval) : "(never)",
                   scene.output.csv_interval > 0 ? fmt::format("{:g} s", scene.output.csv_interval) : "step",
                   scene.output.checkpoint_interval > 0 ? fmt::format("{:g} s", scene.output.checkpoint_interval)
                                                        : "(never)"));
  std::fflush(out);
  if (stability) require_stable_step(*stability, scene.contact, scene.source_file);
}

void require_runnable_size(const Scene& scene) {
  if (scene.effects.fluid)
    require_indexable_fluid_system(scene.cells, FluidSolverOptions{}.ilut_fill_factor, scene.source_file);
}

int run_check_command(const std::string& scene_path, std::FILE* out) {
  const Scene scene = load_scene(scene_path);
  require_runnable_size(scene);
  const Particles particles = generate_particles(scene);
  print_scene_check(scene, particles, out);
  std::fprintf(out, "ok         %s is valid\n", scene_path.c_str());
  return 0;
}

}  // namespace fdem
