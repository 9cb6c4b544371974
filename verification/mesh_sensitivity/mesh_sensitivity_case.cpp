#include "mesh_sensitivity_case.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "coupling/simulation.hpp"

namespace fdem::mesh_sensitivity {

namespace {

// Upper bound of the settling speed [m/s] for sizing the column: the
// isolated-sphere terminal velocity of the 0.76 mm grain is 0.120 m/s
// (reference/settling_reference, eps = 1); 0.13 leaves 8 % margin.
constexpr double kMaxSpeed_m_s = 0.13;

}  // namespace

Scene case_scene(const Scene& base, const CaseSpec& spec) {
  if (base.particles.size() != 1) throw std::invalid_argument("mesh_sensitivity: the base scene has one grain");
  if (spec.width_cells < 1 || spec.width_cells % 2 == 0)
    throw std::invalid_argument("mesh_sensitivity: width_cells must be odd");
  Scene s = base;
  const double d = s.particles[0].size.diameter;
  const double h = spec.ratio * d;
  // Fall distance plus the start cell, a cell of headroom and two below.
  const int nz = static_cast<int>(std::ceil(kMaxSpeed_m_s * spec.end_time_s / h)) + 4;
  const int w = spec.width_cells;
  s.cells = {w, w, nz};
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(w * h, w * h, nz * h);
  const int middle = (w - 1) / 2;
  const double f = spec.start == Start::offset ? 0.25 : 0.5;
  s.particles[0].position = Vec3((middle + f) * h, (middle + f) * h, (nz - 1.5) * h);
  s.coupling.porosity = spec.scheme;
  // The study's diffused runs smooth over one cell (the measured sweep behind
  // kDefaultSmoothingCells), not the scene default of 2 d.
  if (spec.scheme == PorosityScheme::diffused) s.coupling.porosity_smoothing_length = h;
  s.time.end_time = spec.end_time_s;
  return s;
}

CaseResult run_case(const Scene& base, const CaseSpec& spec) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const std::clock_t cpu0 = std::clock();
  const Scene scene = case_scene(base, spec);
  Simulation sim(scene);
  const double h = sim.mesh()->cell_size().x();
  const Vec3 x0 = scene.particles[0].position;

  CaseResult r;
  r.spec = spec;
  while (!sim.finished()) {
    sim.step();
    const Particles& p = sim.particles();
    const Index e = sim.particle_elements()[0];
    r.t_s.push_back(sim.time());
    r.porosity.push_back(e >= 0 ? sim.porosity()[static_cast<std::size_t>(e)] : 1.0);
    r.v_mps.push_back(-p.vz[0]);
    r.element_local.push_back(e >= 0 ? static_cast<int>(e % 5) : -1);
    r.porosity_seconds += sim.diagnostics().coupling_seconds;
    r.lateral_drift_over_cell =
        std::max({r.lateral_drift_over_cell, std::abs(p.x[0] - x0.x()) / h, std::abs(p.y[0] - x0.y()) / h});
  }
  r.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  r.cpu_time_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  r.porosity_mean = plateau_mean(r.t_s, r.porosity, kPlateauStart_s);
  r.vt_mps = plateau_mean(r.t_s, r.v_mps, kPlateauStart_s);
  r.porosity_amp_pct = amplitude_pct(r.t_s, r.porosity, kPlateauStart_s);
  r.velocity_amp_pct = amplitude_pct(r.t_s, r.v_mps, kPlateauStart_s);
  return r;
}

double plateau_mean(const std::vector<double>& t_s, const std::vector<double>& x, double t_from_s) {
  double sum = 0.0;
  long n = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (t_s[i] >= t_from_s - 1e-12) {
      sum += x[i];
      ++n;
    }
  if (n == 0) throw std::invalid_argument("mesh_sensitivity: no sample on the plateau");
  return sum / static_cast<double>(n);
}

double amplitude_pct(const std::vector<double>& t_s, const std::vector<double>& x, double t_from_s) {
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (t_s[i] >= t_from_s - 1e-12) {
      lo = std::min(lo, x[i]);
      hi = std::max(hi, x[i]);
    }
  return 100.0 * (hi - lo) / plateau_mean(t_s, x, t_from_s);
}

std::string start_name(Start start) { return start == Start::offset ? "offset" : "centred"; }

std::string scheme_name(PorosityScheme scheme) {
  // The scene's word without underscores: file names hold lower-case letters
  // and digits only (reports/FORMATS.md, mesh_sensitivity).
  std::string name(porosity_scheme_entry(scheme).name);
  std::erase(name, '_');
  return name;
}

}  // namespace fdem::mesh_sensitivity
