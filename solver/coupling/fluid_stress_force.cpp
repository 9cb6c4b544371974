#include "coupling/fluid_stress_force.hpp"

#include "core/types.hpp"

namespace fdem {

void FluidStressForce::begin_step(const ParticleMapping& mapping, const Particles& particles,
                                  const FluidSolver& fluid) {
  const std::size_t n = particles.size();
  fx_.assign(n, 0.0);
  fy_.assign(n, 0.0);
  fz_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Index e = mapping.element[i];
    if (e < 0) continue;
    const double volume = sphere_volume(particles.diameter[i]);
    const Vec3 grad_p = fluid.pressure_gradient(e);
    fx_[i] = -volume * grad_p.x();
    fy_[i] = -volume * grad_p.y();
    fz_[i] = -volume * grad_p.z();
  }
}

void FluidStressForce::add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) {
  if (inner_) inner_->add(p, fx, fy, fz);
  if (p.size() != fx_.size()) return;
  for (std::size_t i = 0; i < fx_.size(); ++i) {
    fx[i] += fx_[i];
    fy[i] += fy_[i];
    fz[i] += fz_[i];
  }
}

}  // namespace fdem
