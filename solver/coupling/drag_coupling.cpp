#include "coupling/drag_coupling.hpp"

#include <algorithm>
#include <cmath>

namespace fdem {

DragCoupling::DragCoupling(DragLaw law, FluidProperties fluid, bool apply_to_particles)
    : law_(law), fluid_(fluid), apply_(apply_to_particles) {}

void DragCoupling::interpolate(const BoxMesh& mesh, const ParticleMapping& mapping) {
  const std::size_t n = mapping.element.size();
  ux_.resize(n);
  uy_.resize(n);
  uz_.resize(n);
  eps_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Index e = mapping.element[i];
    if (e < 0) {  // outside the mesh: no fluid, no drag (eps = 0 marks it)
      ux_[i] = uy_[i] = uz_[i] = 0.0;
      eps_[i] = 0.0;
      continue;
    }
    const auto& nodes = mesh.element_nodes(e);
    const auto& w = mapping.weights[i];
    double u[3] = {0.0, 0.0, 0.0};
    for (std::size_t a = 0; a < 4; ++a) {  // P1 shape functions = volume coordinates (Eq. 28-31)
      const auto base = 3 * static_cast<std::size_t>(nodes[a]);
      for (std::size_t d = 0; d < 3; ++d) u[d] += w[a] * nodal_velocity_[base + d];
    }
    ux_[i] = u[0];
    uy_[i] = u[1];
    uz_[i] = u[2];
    eps_[i] = porosity_[static_cast<std::size_t>(e)];
  }
}

void DragCoupling::begin_step(const BoxMesh& mesh, const ParticleMapping& mapping,
                              std::span<const double> fluid_velocity, std::span<const double> porosity) {
  mesh_ = &mesh;
  nodal_velocity_ = fluid_velocity;
  porosity_ = porosity;
  interpolate(mesh, mapping);
  const std::size_t n = mapping.element.size();
  mean_x_.assign(n, 0.0);
  mean_y_.assign(n, 0.0);
  mean_z_.assign(n, 0.0);
  evaluations_ = 0;
  remapped_ = false;
}

void DragCoupling::add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) {
  if (p.size() != eps_.size()) {
    // The DEM removed particles mid-step: indices shifted. Map the survivors
    // again (the porosity stays that of the step start) and restart the sums.
    own_mapping_.update(*mesh_, p);
    interpolate(*mesh_, own_mapping_);
    mean_x_.assign(p.size(), 0.0);
    mean_y_.assign(p.size(), 0.0);
    mean_z_.assign(p.size(), 0.0);
    evaluations_ = 0;
    remapped_ = true;
  }
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  const double vp_factor = pi / 6.0;
#pragma omp parallel for if (n > 2048)
  for (std::ptrdiff_t s = 0; s < n; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (eps_[i] <= 0.0) continue;  // outside the mesh
    const double sx = ux_[i] - p.vx[i], sy = uy_[i] - p.vy[i], sz = uz_[i] - p.vz[i];
    const double d = p.diameter[i];
    const double speed = std::sqrt(sx * sx + sy * sy + sz * sz);
    // Eq. 11: f = pi/6 d^3 beta/(1-eps) (u - v)
    const double c = vp_factor * d * d * d * force_coefficient(law_, eps_[i], speed, d, fluid_);
    const double gx = c * sx, gy = c * sy, gz = c * sz;
    mean_x_[i] += gx;
    mean_y_[i] += gy;
    mean_z_[i] += gz;
    if (apply_) {
      fx[i] += gx;
      fy[i] += gy;
      fz[i] += gz;
    }
  }
  ++evaluations_;
}

void DragCoupling::end_step() {
  if (evaluations_ == 0) return;
  const double inv = 1.0 / static_cast<double>(evaluations_);
  for (double& f : mean_x_) f *= inv;
  for (double& f : mean_y_) f *= inv;
  for (double& f : mean_z_) f *= inv;
}

Vec3 DragCoupling::total_mean_drag() const {
  Vec3 total = Vec3::Zero();
  for (std::size_t i = 0; i < mean_x_.size(); ++i) total += Vec3(mean_x_[i], mean_y_[i], mean_z_[i]);
  return total;
}

}  // namespace fdem
