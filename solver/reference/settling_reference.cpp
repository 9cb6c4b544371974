#include "reference/settling_reference.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "reference/brent_root.hpp"

namespace fdem {

namespace {

struct OdeContext {
  const SettlingModel* model;
  Vec3 x0;
};

int settling_rhs(double /*t*/, const double y[], double dydt[], void* params) {
  const auto* ctx = static_cast<const OdeContext*>(params);
  const Vec3 x(ctx->x0.x(), ctx->x0.y(), y[0]);
  dydt[0] = y[1];
  dydt[1] = settling_acceleration(*ctx->model, x, y[1]);
  return std::isfinite(dydt[1]) ? GSL_SUCCESS : GSL_EBADFUNC;
}

double net_weight(const SettlingModel& m) {  // (m - rho_f V_p) g_z [N], Eq. 4-5
  const double vp = sphere_volume(m.diameter_m);
  return (m.particle_density - (m.buoyancy ? m.fluid.density : 0.0)) * vp * m.gravity_z;
}

}  // namespace

double settling_acceleration(const SettlingModel& model, const Vec3& x, double w_m_s) {
  const double vp = sphere_volume(model.diameter_m);
  const double mass = model.particle_density * vp;
  const double eps = model.porosity(x);
  const double k = force_coefficient(drag_law(model.drag), eps, std::abs(w_m_s), model.diameter_m, model.fluid);
  return (net_weight(model) - vp * k * w_m_s) / mass;  // Eq. 1, 3-5, 11 with fluid at rest
}

std::vector<SettlingState> integrate_settling(const SettlingModel& model, const Vec3& x0, double w0_m_s,
                                              std::span<const double> times_s, double abs_tol, double rel_tol) {
  OdeContext ctx{&model, x0};
  gsl_odeiv2_system sys{settling_rhs, nullptr, 2, &ctx};
  const double first_step = 1e-7;  // [s], far below the response time of any grain studied (> 1 ms)
  std::unique_ptr<gsl_odeiv2_driver, decltype(&gsl_odeiv2_driver_free)> driver(
      gsl_odeiv2_driver_alloc_standard_new(&sys, gsl_odeiv2_step_rk8pd, first_step, abs_tol, rel_tol, 1.0, 0.0),
      gsl_odeiv2_driver_free);
  double t = 0.0;
  double y[2] = {x0.z(), w0_m_s};
  std::vector<SettlingState> out;
  out.reserve(times_s.size());
  for (double target : times_s) {
    if (target > t) {
      const int status = gsl_odeiv2_driver_apply(driver.get(), &t, target, y);
      if (status != GSL_SUCCESS)
        throw std::runtime_error(fmt::format("integrate_settling: gsl_odeiv2 failed at t = {} s: {}", t,
                                             gsl_strerror(status)));
    }
    out.push_back({target, y[0], y[1]});
  }
  return out;
}

double terminal_velocity(const SettlingModel& model, double porosity, double rel_tol) {
  const double vp = sphere_volume(model.diameter_m);
  const double weight = std::abs(net_weight(model));
  const DragLawEntry& law = drag_law(model.drag);
  // The speed where the drag balances the net weight (Eq. 11), bracketed by Stokes's.
  const auto excess_drag = [&](double w) {
    return vp * force_coefficient(law, porosity, w, model.diameter_m, model.fluid) * w - weight;
  };
  return brent_root(excess_drag, 0.0, 1.01 * stokes_terminal_velocity(model), rel_tol);
}

double stokes_terminal_velocity(const SettlingModel& model) {
  const double drho = model.particle_density - (model.buoyancy ? model.fluid.density : 0.0);
  return drho * std::abs(model.gravity_z) * model.diameter_m * model.diameter_m / (18.0 * model.fluid.viscosity);
}

}  // namespace fdem
