#include "packed_bed_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <vector>

#include <fmt/format.h>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"

namespace fdem::packed_bed {

BedRun run_bed(Scene scene, FluidModel model, SourceForm source, double superficial_velocity, double z0,
               double z1) {
  const auto t0 = std::chrono::steady_clock::now();
  const double U = superficial_velocity;
  scene.fluid.model = model;
  scene.coupling.source_form = source;
  scene.fluid.faces[4].velocity = Vec3(0, 0, U);  // z_min inlet
  Simulation sim(scene);
  const BoxMesh& mesh = *sim.mesh();
  auto measure = [&](BedRun& r) {
    // Least-squares slope of p(z) over the nodes with z in [z0, z1].
    double n = 0, sz = 0, szz = 0, sp = 0, szp = 0;
    const auto p = sim.fluid_pressure();
    for (Index a = 0; a < mesh.num_nodes(); ++a) {
      const double z = mesh.node(a).z();
      if (z < z0 - 1e-12 || z > z1 + 1e-12) continue;
      const double pa = p[static_cast<std::size_t>(a)];
      n += 1;
      sz += z;
      szz += z * z;
      sp += pa;
      szp += z * pa;
    }
    r.gradient = -(n * szp - sz * sp) / (n * szz - sz * sz);
  };
  BedRun r;
  double previous = 0.0;
  while (!sim.finished()) {
    sim.step();
    previous = r.gradient;
    measure(r);
  }
  r.gradient_change = std::abs(r.gradient - previous) / std::abs(r.gradient);
  // Volume-weighted means over the interior band's elements: the porosity
  // (the central and corner tetrahedra differ, spread reported) and u_z.
  double lo = 1.0, hi = 0.0, fluid = 0.0, volume = 0.0, flow = 0.0;
  const auto u = sim.fluid_velocity();
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const double zc = mesh.element_centroid(e).z();
    double uz = 0.0;
    for (Index a : mesh.element_nodes(e)) uz += u[3 * static_cast<std::size_t>(a) + 2] / 4.0;
    if (zc < z0 || zc > z1) continue;
    const double eps = sim.porosity()[static_cast<std::size_t>(e)], v = mesh.element_volume(e);
    lo = std::min(lo, eps);
    hi = std::max(hi, eps);
    fluid += v * eps;
    flow += v * uz;
    volume += v;
  }
  r.porosity = fluid / volume;
  r.porosity_spread = hi - lo;
  r.interstitial = flow / volume;
  double inverse = 0.0, grains = 0.0;
  const auto elements = sim.particle_elements();
  const Particles& particles = sim.particles();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.z[i] < z0 || particles.z[i] > z1 || elements[i] < 0) continue;
    inverse += 1.0 / sim.porosity()[static_cast<std::size_t>(elements[i])];
    grains += 1.0;
  }
  r.grain_inverse_porosity = r.porosity * inverse / grains;
  {
    // A field of the scene's scheme at the grains' final positions, as the
    // coupling builds it; x / y of grain_means over (eps_e, 1) is the grain's
    // porosity over the part of it the field holds.
    ParticleMapping mapping;
    mapping.update(mesh, particles);
    PorosityField field(mesh, sim.scene().coupling, particles);
    field.update(particles, mapping);
    std::vector<Vec3> weighted(static_cast<std::size_t>(mesh.num_elements()));
    for (std::size_t e = 0; e < weighted.size(); ++e) weighted[e] = Vec3(field.values()[e], 1.0, 0.0);
    std::vector<Vec3> means(particles.size());
    field.grain_means(particles, mapping, weighted, means);
    double sum = 0.0, counted = 0.0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.z[i] < z0 || particles.z[i] > z1 || mapping.element[i] < 0 || means[i].y() <= 0.0) continue;
      sum += means[i].y() / means[i].x();
      counted += 1.0;
    }
    r.grain_volume_inverse_porosity = r.porosity * sum / counted;
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void run_models(const Scene& scene, std::span<const double> reynolds, double z0, double z1,
                const std::function<void(const ModelRun&)>& check) {
  const double d = scene.particles.at(0).size.diameter, rho = scene.fluid.density, mu = scene.fluid.viscosity;
  fmt::print("  Re_p   U [m/s]    eps      model        -dp/dz [Pa/m]   Ergun [Pa/m]   ratio    u/(U/eps)  wall [s]  eps<1/eps_e>  eps<1/eps_grain>\n");
  for (const double re : reynolds)
    for (const ModelSpec& m : kModels) {
      ModelRun r;
      r.model = &m;
      r.reynolds = re;
      r.superficial_velocity = re * mu / (rho * d);
      r.run = run_bed(scene, m.model, m.source, r.superficial_velocity, z0, z1);
      r.ergun = ergun_gradient(r.run.porosity, r.superficial_velocity, d, rho, mu);
      r.ratio = r.run.gradient / r.ergun;
      fmt::print("  {:5.1f}  {:.3e}  {:.4f}  {:11s}  {:.6e}   {:.6e}   {:.4f}   {:.4f}     {:.2f}     {:.4f}        {:.4f}\n", re,
                 r.superficial_velocity, r.run.porosity, m.name, r.run.gradient, r.ergun, r.ratio,
                 r.run.interstitial / (r.superficial_velocity / r.run.porosity), r.run.wall_s, r.run.grain_inverse_porosity,
                 r.run.grain_volume_inverse_porosity);
      check(r);
    }
}

}  // namespace fdem::packed_bed
