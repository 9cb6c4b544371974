#include "fluidized_bed_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "coupling/drag.hpp"
#include "coupling/fluid_stress_force.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "reference/brent_root.hpp"
#include "scene/scene_loader.hpp"
#include "../support/bed_pressure_gradient.hpp"
#include "../support/study_io.hpp"

namespace fdem::fluidized_bed {

double Bed::solid_volume() const { return count * sphere_volume(d); }
double Bed::buoyant_weight() const { return solid_volume() * (rho_p - rho_f) * kGravity; }

// Ergun (1952), Eq. 1, over the bed height (support/bed_pressure_gradient.hpp).
double ergun_drop(const Bed& b, double eps, double U, double height) {
  return height * verification::ergun_gradient(eps, U, b.d, b.rho_f, b.mu);
}

// Ergun's U_mf for porosity eps: Ergun's gradient = (1 - eps)(rho_p - rho_f) g
// (Kunii & Levenspiel 1991, Eq. 3.19).
double ergun_umf(const Bed& b, double eps) {
  const double w = (1 - eps) * (b.rho_p - b.rho_f) * kGravity;
  return brent_root([&](double U) { return ergun_drop(b, eps, U, 1.0) - w; }, 1e-9, 10.0);
}

// Wen & Yu (1966), Chem. Eng. Prog. Symp. Ser. 62(62), 100-111: Re_mf = sqrt(33.7^2 + 0.0408 Ar) - 33.7.
double wen_yu_umf(const Bed& b) {
  const double ar = b.rho_f * (b.rho_p - b.rho_f) * kGravity * b.d * b.d * b.d / (b.mu * b.mu);
  return (std::sqrt(33.7 * 33.7 + 0.0408 * ar) - 33.7) * b.mu / (b.rho_f * b.d);
}

// The simplified model's onset: the drag per bed volume beta(eps, U) U with
// Eq. 12 at the superficial slip equals (1 - eps)(rho_p - rho_f) g; that drag
// is eps times the model's packed gradient (support/bed_pressure_gradient.hpp).
double simplified_umf(const Bed& b, double eps) {
  const double w = (1 - eps) * (b.rho_p - b.rho_f) * kGravity;
  return brent_root([&](double U) { return eps * verification::simplified_gradient(eps, U, b.d, b.rho_f, b.mu) - w; },
                    1e-9, 10.0);
}

// Single-grain terminal velocity with the drag law's own isolated-sphere K
// (ergun_wen_yu at eps = 1: Wen & Yu with Rowe & Henwood's Cd, Eq. 13-14).
double terminal_velocity(const Bed& b) {
  const DragLawEntry& law = drag_law("ergun_wen_yu");
  const FluidProperties fluid{b.rho_f, b.mu};
  const double w = sphere_volume(b.d) * (b.rho_p - b.rho_f) * kGravity;
  return brent_root([&](double v) { return sphere_volume(b.d) * force_coefficient(law, 1.0, v, b.d, fluid) * v - w; },
                    1e-9, 10.0);
}

// Garside & Al-Dibouni (1977), Ind. Eng. Chem. Process Des. Dev. 16(2), 206-214, Eq. 13.
double garside_al_dibouni_n(double re_t) {
  const double x = 0.1 * std::pow(re_t, 0.9);
  return (5.1 + 2.7 * x) / (1.0 + x);
}

// The drag law's homogeneous expansion (Ergun's branch, eps < 0.8).
double ergun_expansion_porosity(const Bed& b, double U) {
  return brent_root([&](double e) { return ergun_drop(b, e, U, 1.0) - (1 - e) * (b.rho_p - b.rho_f) * kGravity; },
                    0.2, 0.7999);
}

double profile_ergun_drop(const Bed& b, const std::vector<double>& layer_porosity, double layer_height, double U) {
  double drop = 0.0;
  for (const double eps : layer_porosity) drop += ergun_drop(b, eps, U, layer_height);
  return drop;
}

double profile_ergun_umf(const Bed& b, const std::vector<double>& layer_porosity, double layer_height) {
  const double w = b.buoyant_weight_per_area();
  return brent_root([&](double U) { return profile_ergun_drop(b, layer_porosity, layer_height, U) - w; }, 1e-9, 10.0);
}

double slab_solid_volume(const Particles& grains, double a, double b) {
  // Volume of a sphere of radius r below the plane at height s above its
  // lowest point: the cap pi s^2 (3 r - s) / 3, s clamped to [0, 2 r].
  auto below = [](double r, double s) {
    s = std::clamp(s, 0.0, 2.0 * r);
    return std::numbers::pi * s * s * (3.0 * r - s) / 3.0;
  };
  double v = 0.0;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const double r = 0.5 * grains.diameter[i], bottom = grains.z[i] - r;
    v += below(r, b - bottom) - below(r, a - bottom);
  }
  return v;
}

namespace {

// Dry settle: the scene's grains from their random start under gravity, the
// DEM alone, written as a particle CSV the coupled runs load (every fluid
// model and setting starts from the same bed).
std::string settle_dry(const Scene& base, double dry_settle_s, const std::string& csv_path, double* max_speed) {
  Scene dry = base;
  dry.effects.fluid = false;
  dry.effects.coupling = CouplingMode::off;
  dry.effects.buoyancy = false;
  dry.time.end_time = dry_settle_s;
  Simulation sim(dry);
  while (!sim.finished()) sim.step();
  const Particles& p = sim.particles();
  std::ofstream out(csv_path);
  out << "id,d,rho,x,y,z\n";
  double vmax = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    out << fmt::format("{},{},{},{},{},{}\n", i, p.diameter[i], base.particles.at(0).density, p.x[i], p.y[i], p.z[i]);
    vmax = std::max(vmax, std::sqrt(p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]));
  }
  *max_speed = vmax;
  return csv_path;
}

double mean_height(const Particles& p) {
  double s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) s += p.z[i];
  return 2.0 * s / static_cast<double>(p.size());
}

Vec3 element_pressure_gradient(const BoxMesh& mesh, std::span<const double> p, Index e) {
  Vec3 g = Vec3::Zero();
  const auto& grad = mesh.shape_gradients(e);
  for (int a = 0; a < 4; ++a) {
    const double pa = p[static_cast<std::size_t>(mesh.element_nodes(e)[static_cast<std::size_t>(a)])];
    g += pa * Vec3(grad(a, 0), grad(a, 1), grad(a, 2));
  }
  return g;
}

// The mean over the grains of their element's porosity: the porosity their
// drag is computed with (coupling/drag_coupling.hpp).
double mean_grain_porosity(const Simulation& sim) {
  const auto eps = sim.porosity();
  const auto elements = sim.particle_elements();
  double sum = 0.0;
  long n = 0;
  for (const Index e : elements)
    if (e >= 0) {
      sum += eps[static_cast<std::size_t>(e)];
      ++n;
    }
  return n > 0 ? sum / static_cast<double>(n) : 1.0;
}

// A closed-form gradient summed over the mesh's cell layers, each at its own
// mean element porosity (volume-weighted): the bed's axial porosity profile
// (looser at the floor, the solid the porosity scheme spreads past the bed's
// top and bottom), which the bed porosity from H = 2 <z> averages. Layers
// without solid add nothing (both gradients vanish at eps = 1).
template <class Gradient>
double layered_drop(const Simulation& sim, Gradient&& gradient) {
  const BoxMesh& mesh = *sim.mesh();
  const int nz = sim.scene().cells[2];
  const double dz = (sim.scene().domain.upper.z() - sim.scene().domain.lower.z()) / nz;
  std::vector<double> fluid(static_cast<std::size_t>(nz), 0.0), volume(static_cast<std::size_t>(nz), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto layer = static_cast<std::size_t>(std::clamp(static_cast<int>(mesh.element_centroid(e).z() / dz), 0, nz - 1));
    fluid[layer] += mesh.element_volume(e) * sim.porosity()[static_cast<std::size_t>(e)];
    volume[layer] += mesh.element_volume(e);
  }
  double drop = 0.0;
  for (std::size_t k = 0; k < fluid.size(); ++k) drop += dz * gradient(fluid[k] / volume[k]);
  return drop;
}

// The exact porosity of each layer of thickness `layer` from the floor up to
// `height` (slab_solid_volume): with the mesh's cell layers, Ergun summed
// over them is the drop an element porosity of this cell size could give at
// best, with no solid spread past the bed's ends and no scatter between
// elements; against Ergun at the bed's mean porosity it measures what the
// bed's own ends (the looser floor layer, the part-filled top layer) cost.
std::vector<double> exact_layer_porosities(const Particles& grains, const Bed& bed, double height, double layer) {
  const auto count = static_cast<int>(std::lround(height / layer));
  std::vector<double> eps(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k)
    eps[static_cast<std::size_t>(k)] = 1.0 - slab_solid_volume(grains, k * layer, (k + 1) * layer) / (bed.area * layer);
  return eps;
}

// The drop the semi-implicit exchange's coefficients would give if the
// fluid crossed every element at the superficial velocity U (no channeling):
// sum_e V_e beta_e U / A, beta_e as handed to the fluid (the simplified
// model's already over eps_e). Against the drop it does give, sum_e V_e
// beta_e <u_z>_e / A at rest, it says how much the flow avoids the elements
// of large beta. Both window means, like Delta p.
struct ExchangeDrops {
  double plug = 0.0, actual = 0.0;  // [Pa]
};
ExchangeDrops exchange_drops(const Simulation& sim, const Bed& bed, double U) {
  const BoxMesh& mesh = *sim.mesh();
  const auto beta = sim.momentum_exchange_beta();
  const auto u = sim.fluid_velocity();
  ExchangeDrops out;
  if (beta.empty()) return out;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    double uz = 0.0;
    for (Index a : mesh.element_nodes(e)) uz += 0.25 * u[3 * static_cast<std::size_t>(a) + 2];
    const double vb = mesh.element_volume(e) * beta[static_cast<std::size_t>(e)];
    out.plug += vb * U / bed.area;
    out.actual += vb * uz / bed.area;
  }
  return out;
}

// The bed's vertical momentum balance after a step, each term over W. Model
// A's grains feel the drag and their share of the projected pressure
// gradient (coupling/fluid_stress_force.hpp; the other models' grains feel
// the drag alone, grain_pressure 0); the fluid's momentum carries the same
// drag with -eps_h grad p (Eq. 18-19), eps_h the P1 porosity the fluid makes
// from the element values (fluid/fluid_solver.hpp). In a steady, fluidized bed:
//   W = drag + grain_pressure + floor_load   (grains; frictionless side walls)
//   drag = fluid_pressure = int eps_h (-dp/dz)       (fluid)
//   grain_pressure = solid_pressure = int (1 - eps_h)(-dp/dz)   (exchange)
// so Delta p A = fluid_pressure + solid_pressure = W - floor_load. The
// discrete terms show which equality a shortfall of the plateau breaks.
struct Balance {
  double drag = 0, grain_pressure = 0, fluid_pressure = 0, solid_pressure = 0;
};

// Element pressure gradients, and the element mean of the fluid's eps_h.
struct FluidFields {
  std::vector<Vec3> gradient;
  std::vector<double> porosity;
};
FluidFields fluid_fields(const Simulation& sim) {
  const BoxMesh& mesh = *sim.mesh();
  const auto p = sim.fluid_pressure();
  const auto eps = sim.porosity();
  const auto ne = static_cast<std::size_t>(mesh.num_elements()), nn = static_cast<std::size_t>(mesh.num_nodes());
  std::vector<double> fluid(nn, 0.0), weight(nn, 0.0);
  FluidFields f{std::vector<Vec3>(ne), std::vector<double>(ne, 0.0)};
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    f.gradient[static_cast<std::size_t>(e)] = element_pressure_gradient(mesh, p, e);
    for (Index a : mesh.element_nodes(e)) {
      fluid[static_cast<std::size_t>(a)] += mesh.element_volume(e) * eps[static_cast<std::size_t>(e)];
      weight[static_cast<std::size_t>(a)] += mesh.element_volume(e);
    }
  }
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index a : mesh.element_nodes(e))
      f.porosity[static_cast<std::size_t>(e)] += 0.25 * fluid[static_cast<std::size_t>(a)] / weight[static_cast<std::size_t>(a)];
  return f;
}

// The grains' pressure force as model A gives it, from a porosity field of
// the scene's scheme refreshed at the grains' present positions.
class GrainPressureProbe {
 public:
  explicit GrainPressureProbe(const Simulation& sim)
      : porosity_(*sim.mesh(), sim.scene().coupling, sim.particles()), active_(sim.scene().fluid.model == FluidModel::vans_a) {}
  // -V_p (grad p)_z felt by each grain (zero unless model A).
  std::vector<double> felt_z(const Simulation& sim, std::span<const Vec3> gradient) {
    const Particles& grains = sim.particles();
    std::vector<double> out(grains.size(), 0.0);
    if (!active_) return out;
    mapping_.update(*sim.mesh(), grains);
    porosity_.update(grains, mapping_);
    shares_.resize(grains.size());
    grain_pressure_gradients(*sim.mesh(), gradient, porosity_, mapping_, grains, shares_);
    for (std::size_t i = 0; i < grains.size(); ++i) out[i] = -sphere_volume(grains.diameter[i]) * shares_[i].z();
    return out;
  }

 private:
  PorosityField porosity_;
  ParticleMapping mapping_;
  std::vector<Vec3> shares_;
  bool active_;
};

Balance balance(const Simulation& sim, const Bed& bed, GrainPressureProbe& probe) {
  const BoxMesh& mesh = *sim.mesh();
  const FluidFields f = fluid_fields(sim);
  Balance b;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto k = static_cast<std::size_t>(e);
    const double g = -f.gradient[k].z(), v = mesh.element_volume(e);
    b.fluid_pressure += v * f.porosity[k] * g;
    b.solid_pressure += v * (1 - f.porosity[k]) * g;
  }
  for (const double fz : probe.felt_z(sim, f.gradient)) b.grain_pressure += fz;
  b.drag = sim.diagnostics().drag_on_particles.z();
  const double w = bed.buoyant_weight();
  b.drag /= w;
  b.grain_pressure /= w;
  b.fluid_pressure /= w;
  b.solid_pressure /= w;
  return b;
}

// The same balance per cell layer, printed at each stage's end when
// FDEM_FB_LAYERS is set (README 'Plateau': where the discrete terms sit).
// The drag per layer is the fluid's side, beta_e <u>_e V_e: at rest the
// grains' velocity is zero, so it is exact in the packed stages only.
void print_layer_balance(const Simulation& sim, const Bed& bed, double factor, double bed_porosity, GrainPressureProbe& probe) {
  const BoxMesh& mesh = *sim.mesh();
  const int nz = sim.scene().cells[2];
  const double dz = (sim.scene().domain.upper.z() - sim.scene().domain.lower.z()) / nz;
  const auto u = sim.fluid_velocity();
  const auto beta = sim.momentum_exchange_beta();
  const FluidFields f = fluid_fields(sim);
  auto layer_of = [&](double z) { return static_cast<std::size_t>(std::clamp(static_cast<int>(z / dz), 0, nz - 1)); };
  std::vector<double> ex(static_cast<std::size_t>(nz), 0.0), eg(ex.size(), 0.0), sg(ex.size(), 0.0), gp(ex.size(), 0.0);
  std::vector<double> fluid(ex.size(), 0.0), volume(ex.size(), 0.0), weight(ex.size(), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto k = layer_of(mesh.element_centroid(e).z());
    fluid[k] += mesh.element_volume(e) * sim.porosity()[static_cast<std::size_t>(e)];
    volume[k] += mesh.element_volume(e);
    double uz = 0;
    for (Index a : mesh.element_nodes(e)) uz += u[3 * static_cast<std::size_t>(a) + 2] / 4.0;
    const auto K = static_cast<std::size_t>(e);
    const double g = -f.gradient[K].z(), v = mesh.element_volume(e);
    ex[k] += v * beta[K] * uz;
    eg[k] += v * f.porosity[K] * g;
    sg[k] += v * (1 - f.porosity[K]) * g;
  }
  const Particles& grains = sim.particles();
  const std::vector<double> felt = probe.felt_z(sim, f.gradient);
  for (std::size_t i = 0; i < grains.size(); ++i) {
    gp[layer_of(grains.z[i])] += felt[i];
    weight[layer_of(grains.z[i])] += sphere_volume(grains.diameter[i]) * (bed.rho_p - bed.rho_f) * kGravity;
  }
  const double w = bed.buoyant_weight();
  // What each layer's grains lay on the layers below (their weight less the
  // fluid's drag and pressure force on them, over W): summed, the floor's
  // load (README 'Plateau near the onset'). Split: the floor layer, the
  // layers between, the top layer holding grains (> 5 % of W) and above.
  int top = 0;
  for (int k = 0; k < nz; ++k)
    if (weight[static_cast<std::size_t>(k)] > 0.05 * w) top = k;
  double floor_layer = 0.0, between = 0.0, top_layers = 0.0;
  for (int k = 0; k < nz; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const double laid = (weight[K] - ex[K] - gp[K]) / w;
    (k == 0 ? floor_layer : k < top ? between : top_layers) += laid;
  }
  fmt::print("    layers' weight less drag and pressure force at {:.2f} U_mf, over W: floor layer {:+.4f}, layers 1-{} {:+.4f}, "
             "top layer {} (eps {:.3f}, fluid holds {:.2f} of its weight) and above {:+.4f}; sum {:+.4f}\n",
             factor, floor_layer, top - 1, between, top, fluid[static_cast<std::size_t>(top)] / volume[static_cast<std::size_t>(top)],
             (ex[static_cast<std::size_t>(top)] + gp[static_cast<std::size_t>(top)]) / weight[static_cast<std::size_t>(top)],
             top_layers, floor_layer + between + top_layers);
  for (int k = 0; k < nz; ++k) {
    const auto K = static_cast<std::size_t>(k);
    if (ex[K] < 1e-4 * w && k > 1) continue;
    fmt::print("    layer balance at {:.2f} U_mf, layer {:2d} (eps {:.3f}, Ergun U_mf {:.2f} of the bed's) / W: weight {:.4f} "
               "beta <u> {:.4f} int eps G {:.4f} (diff {:+.4f}) | grains V G {:.4f} int (1-eps) G {:.4f} (diff {:+.4f})\n",
               factor, k, fluid[K] / volume[K], ergun_umf(bed, fluid[K] / volume[K]) / ergun_umf(bed, bed_porosity), weight[K] / w,
               ex[K] / w, eg[K] / w, (eg[K] - ex[K]) / w, gp[K] / w, sg[K] / w, (gp[K] - sg[K]) / w);
  }
}

}  // namespace

Prepared prepare(const std::string& scene_file, double dry_settle_s, FluidModel model, SourceForm form,
                 const Settings& settings, const std::vector<double>& factors, const std::string& tag) {
  Prepared p;
  const Scene base = load_scene(scene_file);
  p.bed.d = base.particles.at(0).size.diameter;
  p.bed.rho_p = base.particles.at(0).density;
  p.bed.rho_f = base.fluid.density;
  p.bed.mu = base.fluid.viscosity;
  p.bed.count = base.particles.at(0).count;
  p.bed.area = (base.domain.upper.x() - base.domain.lower.x()) * (base.domain.upper.y() - base.domain.lower.y());
  const std::string dir = study::results_dir("fluidized_bed");
  std::filesystem::create_directories(dir);
  const std::string csv = settle_dry(base, dry_settle_s, fmt::format("{}/settled_bed_{}.csv", dir, tag), &p.settle_speed);
  p.scene = base;
  ParticleSet& set = p.scene.particles.at(0);
  set.placement = PlacementKind::csv;
  set.csv_file = csv;
  p.scene.fluid.model = model;
  p.scene.coupling.source_form = form;
  p.scene.coupling.exchange = MomentumExchange::semi_implicit;
  if (settings.cell_size > 0.0)
    for (int a = 0; a < 3; ++a) {
      const double extent = p.scene.domain.upper[a] - p.scene.domain.lower[a];
      p.scene.cells[static_cast<std::size_t>(a)] = static_cast<int>(std::lround(extent / settings.cell_size));
    }
  if (settings.set_porosity) p.scene.coupling.porosity = settings.porosity;
  if (settings.fluid_step > 0.0) {
    p.scene.time.fluid_step = settings.fluid_step;
    p.scene.time.subcycles = 0;  // fluid_step / dem_step
  }
  if (settings.set_exchange) p.scene.coupling.exchange = settings.exchange;
  {
    Scene probe = p.scene;
    probe.effects.fluid = false;
    probe.effects.coupling = CouplingMode::off;
    const Simulation s(probe);
    p.settled_height = mean_height(s.particles());
  }
  p.settled_porosity = p.bed.porosity(p.settled_height);
  p.umf_ergun = ergun_umf(p.bed, p.settled_porosity);
  p.factors = factors;
  for (double f : factors) p.velocities.push_back(f * p.umf_ergun);
  fmt::print("Fluidized bed ({}): {} grains of d = {} mm, settled H = {:.3f} mm, eps = {:.4f}, "
             "Ergun U_mf = {:.4e} m/s, Wen-Yu U_mf = {:.4e} m/s, W/A = {:.4f} Pa (dry settle: max speed {:.2e} m/s)\n",
             tag, p.bed.count, p.bed.d * 1e3, p.settled_height * 1e3, p.settled_porosity, p.umf_ergun,
             wen_yu_umf(p.bed), p.bed.buoyant_weight_per_area(), p.settle_speed);
  return p;
}

BedRun run_stages(const Prepared& prep, const std::string& model, double packed_s, double moving_s,
                  bool bed_stays_packed) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene& scene = prep.scene;
  const Bed& bed = prep.bed;
  Simulation sim(scene);
  GrainPressureProbe probe(sim);
  const BoxMesh& mesh = *sim.mesh();
  // Each face's pressure integral over its area, int p dA / A, exactly for
  // the P1 pressure (a third of each boundary triangle's area to each of its
  // nodes), so that Delta p A = int (-dp/dz) dV: the force on the column's
  // contents. The plain mean of the face's nodes weights the wall and corner
  // nodes like the interior ones; it is kept beside (drop_nodal).
  const double ztop = scene.domain.upper.z();
  const auto nn = static_cast<std::size_t>(mesh.num_nodes());
  std::vector<double> bottom(nn, 0.0), top(nn, 0.0), bottom_nodal(nn, 0.0), top_nodal(nn, 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    for (auto [plane, z0] : {std::pair{&bottom, 0.0}, std::pair{&top, ztop}}) {
      std::vector<Index> on;
      for (Index a : mesh.element_nodes(e))
        if (std::abs(mesh.node(a).z() - z0) < 1e-12) on.push_back(a);
      if (on.size() != 3) continue;
      const Vec3 u = mesh.node(on[1]) - mesh.node(on[0]), v = mesh.node(on[2]) - mesh.node(on[0]);
      const double area = 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());  // the triangle lies in a plane z = z0
      for (Index a : on) (*plane)[static_cast<std::size_t>(a)] += area / 3.0;
    }
  }
  for (std::size_t a = 0; a < nn; ++a) {
    bottom_nodal[a] = bottom[a] > 0.0 ? 1.0 : 0.0;
    top_nodal[a] = top[a] > 0.0 ? 1.0 : 0.0;
  }
  // Every node plane's pressure mean the same way (int p dA / A over the
  // plane; an interior plane's triangles are faces of the elements on both
  // sides, each counted twice alike): the interior band's taps.
  const int nz = scene.cells[2];
  const double dz = (ztop - scene.domain.lower.z()) / nz;
  std::vector<double> plane_weight(nn, 0.0);
  std::vector<int> plane_of(nn, 0);
  for (Index a = 0; a < mesh.num_nodes(); ++a)
    plane_of[static_cast<std::size_t>(a)] = static_cast<int>(std::lround(mesh.node(a).z() / dz));
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto nodes = mesh.element_nodes(e);
    for (int k = 0; k <= nz; ++k) {
      std::vector<Index> on;
      for (Index a : nodes)
        if (plane_of[static_cast<std::size_t>(a)] == k) on.push_back(a);
      if (on.size() != 3) continue;
      const Vec3 u = mesh.node(on[1]) - mesh.node(on[0]), v = mesh.node(on[2]) - mesh.node(on[0]);
      const double area = 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());
      for (Index a : on) plane_weight[static_cast<std::size_t>(a)] += area / 3.0;
    }
  }
  auto plane_pressure = [&](int k) {
    const auto p = sim.fluid_pressure();
    double s = 0.0, w = 0.0;
    for (std::size_t a = 0; a < nn; ++a)
      if (plane_of[a] == k) {
        s += plane_weight[a] * p[a];
        w += plane_weight[a];
      }
    return s / w;
  };
  auto plane_mean = [&](const std::vector<double>& weight) {
    const auto p = sim.fluid_pressure();
    double s = 0.0, w = 0.0;
    for (std::size_t a = 0; a < nn; ++a) {
      s += weight[a] * p[a];
      w += weight[a];
    }
    return s / w;
  };
  BedRun run;
  run.model = model;
  bool previous_packed = true;
  for (std::size_t k = 0; k < prep.velocities.size(); ++k) {
    Stage st;
    st.factor = prep.factors[k];
    st.velocity = prep.velocities[k];
    st.rising = k == 0 || prep.velocities[k] > prep.velocities[k - 1];
    sim.set_inlet_velocity(BoxFace::z_min, Vec3(0, 0, st.velocity));
    const bool packed = st.factor < 1.0;
    const double length = (packed && previous_packed) || bed_stays_packed ? packed_s : moving_s;
    previous_packed = packed;
    const long steps = std::lround(length / sim.step_size());
    std::vector<double> drops, heights;
    double nodal_sum = 0.0, grain_porosity_sum = 0.0;
    double interior_gradient_sum = 0.0, interior_porosity_sum = 0.0, interior_scheme_sum = 0.0;
    int plane_lo = 0, plane_hi = 0;
    ExchangeDrops exchange_sum;
    Balance sum;
    for (long s = 0; s < steps; ++s) {
      sim.step();
      run.outside = std::max(run.outside, sim.diagnostics().particles_outside_mesh);
      if (2 * s >= steps && drops.empty()) {
        // The interior band, fixed for the window from the bed at its start.
        double bed_top = 0.0;
        for (std::size_t i = 0; i < sim.particles().size(); ++i)
          bed_top = std::max(bed_top, sim.particles().z[i] + 0.5 * sim.particles().diameter[i]);
        st.band_lower = dz;
        st.band_upper = bed_top - 2.0 * bed.d - dz;
        plane_lo = static_cast<int>(std::ceil(st.band_lower / dz - 1e-9));
        plane_hi = static_cast<int>(std::floor(st.band_upper / dz + 1e-9));
        st.band_planes = std::max(0, plane_hi - plane_lo + 1);
      }
      if (2 * s >= steps) {
        drops.push_back(plane_mean(bottom) - plane_mean(top));
        if (st.band_planes >= 2) {
          const double z0 = plane_lo * dz, z1 = plane_hi * dz;
          interior_gradient_sum += (plane_pressure(plane_lo) - plane_pressure(plane_hi)) / (z1 - z0);
          interior_porosity_sum += 1.0 - slab_solid_volume(sim.particles(), z0, z1) / (bed.area * (z1 - z0));
          double fluid = 0.0, volume = 0.0;
          for (Index e = 0; e < mesh.num_elements(); ++e) {
            const double zc = mesh.element_centroid(e).z();
            if (zc < z0 || zc > z1) continue;
            fluid += mesh.element_volume(e) * sim.porosity()[static_cast<std::size_t>(e)];
            volume += mesh.element_volume(e);
          }
          interior_scheme_sum += fluid / volume;
        }
        nodal_sum += plane_mean(bottom_nodal) - plane_mean(top_nodal);
        heights.push_back(mean_height(sim.particles()));
        const Balance b = balance(sim, bed, probe);
        const ExchangeDrops ex = exchange_drops(sim, bed, st.velocity);
        exchange_sum.plug += ex.plug;
        exchange_sum.actual += ex.actual;
        grain_porosity_sum += mean_grain_porosity(sim);
        sum.drag += b.drag;
        sum.grain_pressure += b.grain_pressure;
        sum.fluid_pressure += b.fluid_pressure;
        sum.solid_pressure += b.solid_pressure;
      }
    }
    const auto n = static_cast<double>(drops.size());
    double total = 0, sq = 0, first = 0, second = 0, h = 0;
    for (std::size_t i = 0; i < drops.size(); ++i) {
      total += drops[i];
      (2 * i < drops.size() ? first : second) += drops[i];
      h += heights[i];
    }
    st.drop = total / n;
    st.drop_nodal = nodal_sum / n;
    for (double x : drops) sq += (x - st.drop) * (x - st.drop);
    st.drop_sd = std::sqrt(sq / n);
    st.drop_first = first / std::floor(n / 2 + 0.5);
    st.drop_second = second / (n - std::floor(n / 2 + 0.5));
    st.height = h / n;
    st.porosity = bed.porosity(st.height);
    st.layered_ergun = layered_drop(sim, [&](double e) { return verification::ergun_gradient(e, st.velocity, bed.d, bed.rho_f, bed.mu); });
    st.layered_simplified = layered_drop(sim, [&](double e) { return verification::simplified_gradient(e, st.velocity, bed.d, bed.rho_f, bed.mu); });
    st.exchange_plug_drop = exchange_sum.plug / n;
    st.exchange_drop = exchange_sum.actual / n;
    st.grain_porosity = grain_porosity_sum / n;
    if (st.band_planes >= 2) {
      st.band_lower = plane_lo * dz;  // the taps: the band's outermost node planes
      st.band_upper = plane_hi * dz;
      st.interior_gradient = interior_gradient_sum / n;
      st.interior_porosity = interior_porosity_sum / n;
      st.interior_scheme_porosity = interior_scheme_sum / n;
    }
    st.layer_height = dz;
    st.exact_layer_porosity = exact_layer_porosities(sim.particles(), bed, ztop - scene.domain.lower.z(), dz);
    st.exact_layered_ergun = profile_ergun_drop(bed, st.exact_layer_porosity, dz, st.velocity);
    {
      // The same at the grain's scale (slabs of one diameter): how much the
      // profile's resolution moves the reference (README 'Packed branch').
      const double column = ztop - scene.domain.lower.z();
      const int slabs = static_cast<int>(std::lround(column / bed.d));
      st.grain_layered_ergun = profile_ergun_drop(bed, exact_layer_porosities(sim.particles(), bed, column, column / slabs),
                                                  column / slabs, st.velocity);
    }
    st.drag = sum.drag / n;
    st.grain_pressure = sum.grain_pressure / n;
    st.fluid_pressure = sum.fluid_pressure / n;
    st.solid_pressure = sum.solid_pressure / n;
    st.floor_load = 1.0 - st.drag - st.grain_pressure;
    st.pressure_integral = st.fluid_pressure + st.solid_pressure;
    run.stages.push_back(st);
    if (std::getenv("FDEM_FB_LAYERS") != nullptr) print_layer_balance(sim, bed, st.factor, prep.settled_porosity, probe);
    fmt::print("  {:10s} U = {:.4e} m/s ({:.2f} U_mf) {:7s} dp = {:9.4f} Pa (sd {:.4f}, halves {:.4f} {:.4f}) "
               "H = {:.3f} mm eps = {:.4f} layered Ergun {:.4f} Pa\n"
               "             / W: drag {:.4f} grains' -V dp/dz {:.4f} floor {:.4f} | int eps(-dp/dz) {:.4f} "
               "int (1-eps)(-dp/dz) {:.4f} dp A {:.4f} (nodal mean {:.4f})\n",
               model, st.velocity, st.factor, st.rising ? "rising" : "falling", st.drop, st.drop_sd, st.drop_first,
               st.drop_second, st.height * 1e3, st.porosity, st.layered_ergun, st.drag, st.grain_pressure,
               st.floor_load, st.fluid_pressure, st.solid_pressure, st.drop / bed.buoyant_weight_per_area(),
               st.drop_nodal / bed.buoyant_weight_per_area());
    if (st.band_planes >= 2)
      fmt::print("             interior {:.1f}-{:.1f} mm ({} planes): -dp/dz {:.2f} Pa/m, eps exact {:.4f} (scheme {:.4f}), "
                 "over Ergun there {:.4f}; dp over Ergun at the cell layers' exact eps {:.4f}, that over Ergun at the bed's {:.4f}\n",
                 st.band_lower * 1e3, st.band_upper * 1e3, st.band_planes, st.interior_gradient, st.interior_porosity,
                 st.interior_scheme_porosity,
                 st.interior_gradient / verification::ergun_gradient(st.interior_porosity, st.velocity, bed.d, bed.rho_f, bed.mu),
                 st.drop / st.exact_layered_ergun, st.exact_layered_ergun / ergun_drop(bed, st.porosity, st.velocity, st.height));
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

double onset_velocity(const std::vector<Stage>& s, double plateau) {
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (const Stage& x : s) {
    const double u = x.velocity, u2 = u * u;
    s11 += u * u;
    s12 += u * u2;
    s22 += u2 * u2;
    r1 += u * x.drop;
    r2 += u2 * x.drop;
  }
  const double det = s11 * s22 - s12 * s12;
  const double a = (r1 * s22 - r2 * s12) / det, b = (s11 * r2 - s12 * r1) / det;
  return (-a + std::sqrt(a * a + 4 * b * plateau)) / (2 * b);
}

std::vector<Stage> select(const std::vector<Stage>& s, bool rising, bool packed) {
  std::vector<Stage> out;
  for (const Stage& x : s)
    if (x.rising == rising && (x.factor < 1.0) == packed) out.push_back(x);
  return out;
}

Summary summarize(const BedRun& run, const Bed& b) {
  Summary out;
  for (const Stage& s : select(run.stages, true, true)) {
    const double r = s.drop / ergun_drop(b, s.porosity, s.velocity, s.height);
    if (std::abs(r - 1) > std::abs(out.packed_over_ergun_worst - 1)) out.packed_over_ergun_worst = r;
  }
  double sum = 0.0;
  int n = 0;
  for (const Stage& s : run.stages) {
    if (s.factor < 1.0) continue;
    const double r = s.drop / b.buoyant_weight_per_area();
    if (std::abs(r - 1) > std::abs(out.plateau_over_weight_worst - 1)) out.plateau_over_weight_worst = r;
    sum += s.drop;
    ++n;
  }
  out.plateau_mean = sum / n;
  out.umf_curve = onset_velocity(select(run.stages, true, true), out.plateau_mean);
  out.umf_curve_over_ergun = out.umf_curve / ergun_umf(b, run.stages.front().porosity);
  return out;
}

}  // namespace fdem::fluidized_bed
