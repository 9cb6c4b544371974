#pragma once
// Reference solutions for a single particle settling in fluid at rest, with
// GSL, solving the SAME model as the coupled solver (paper Eq. 1-5, 11-15):
//
//   m dw/dt = -(m - rho_f V_p) g_z ... written for the vertical axis:
//   m dw/dt = m g - rho_f V_p g + V_p K(eps(x), |w|) (0 - w),   dz/dt = w
//
// with g the gravity vector (its z component, negative downward), buoyancy
// optional (Eq. 5), K = beta/(1 - eps) the drag force coefficient of
// coupling/drag.hpp (Eq. 11-15: the law as written, in double; the
// solver's subcycle evaluates Wen & Yu's Re^0.687 in single precision,
// within 2e-7 of it, drag_laws/ergun_wen_yu.hpp), and eps(x) the porosity
// of the element the particle is in, passed as a callable of the position (it may jump when the
// particle crosses an element face; the integrator's step control finds the
// jump). No added mass, no history force: the model has none.
//
// integrate_settling: gsl_odeiv2 with the embedded Runge-Kutta Prince-Dormand
// (8,9) stepper (rk8pd) and absolute/relative error control.
// terminal_velocity: gsl_root_fsolver_brent on weight - buoyancy = drag.
// stokes_terminal_velocity: the analytic limit (rho_p - rho_f) g d^2 / (18 mu).
#include <functional>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "coupling/drag.hpp"
#include "scene/scene.hpp"

namespace fdem {

struct SettlingModel {
  double diameter_m = 0.0;
  double particle_density = 2650.0;   // [kg/m^3]
  FluidProperties fluid;
  double gravity_z = -9.81;           // [m/s^2], vertical component
  bool buoyancy = true;               // Eq. 5
  std::string drag = "ergun_wen_yu";  // a law of drag_laws/drag_law_table.cpp
  /// Porosity seen by the particle at a position (default: 1, an isolated sphere).
  std::function<double(const Vec3&)> porosity = [](const Vec3&) { return 1.0; };
};

struct SettlingState {
  double time_s = 0.0;
  double z_m = 0.0;
  double w_m_s = 0.0;        // vertical velocity (negative when falling)
};

/// Vertical acceleration [m/s^2] at position x (only z changes) and velocity w.
double settling_acceleration(const SettlingModel& model, const Vec3& x, double w_m_s);

/// States at the requested times (ascending, >= 0), from start position x0
/// (x and y stay fixed) and vertical velocity w0. Tolerances are for the
/// gsl_odeiv2 error control (absolute on z [m] and w [m/s], relative).
std::vector<SettlingState> integrate_settling(const SettlingModel& model, const Vec3& x0, double w0_m_s,
                                              std::span<const double> times_s, double abs_tol = 1e-14,
                                              double rel_tol = 1e-12);

/// Terminal settling SPEED (> 0) at constant porosity eps, by Brent's method
/// on (m - rho_f V_p) |g| = V_p K(eps, w) w, bracketed by [0, Stokes speed]
/// (every closure's K is at least Stokes' 18 mu / d^2 for eps <= 1, Eq. 13
/// with eps^-2.65 >= 1, Eq. 12 with (1-eps)/eps >= 0.25).
double terminal_velocity(const SettlingModel& model, double porosity, double rel_tol = 1e-13);

/// Stokes' law: (rho_p - rho_f) |g| d^2 / (18 mu) [m/s] (rho_f only with buoyancy).
double stokes_terminal_velocity(const SettlingModel& model);

}  // namespace fdem
