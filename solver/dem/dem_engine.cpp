// DEM engine: effect-specialised kernels behind one class (see dem_engine.hpp).
#include "dem/dem_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "dem/contact_law.hpp"
#include "dem/neighbour_list.hpp"
#include "dem/stability.hpp"

namespace fdem {

/// State shared by every specialisation; the effect-specific work is in
/// KernelFor<...>::step_impl and ::forces.
class DemEngine::Kernel {
 public:
  Kernel(Particles particles, const Scene& scene) : p_(std::move(particles)), domain_(scene.domain) {
    const Effects& e = scene.effects;
    dt_ = scene.time.dem_step;
    if (!(dt_ > 0.0))
      throw InputError(scene.source_file, "time.dem_step", fmt::format("{:g}", dt_), "the DEM step must be positive");
    const std::size_t n = p_.size();
    if (p_.mass.size() != n || p_.diameter.size() != n || p_.vx.size() != n)
      throw std::invalid_argument("DemEngine: particle arrays of unequal length");
    for (std::size_t i = 0; i < n; ++i)
      if (!(p_.diameter[i] > 0.0) || !(p_.mass[i] > 0.0))
        throw InputError(scene.source_file, "particles", fmt::format("particle {} d={:g} m={:g}", i, p_.diameter[i], p_.mass[i]),
                         "every particle needs a positive diameter and mass");
    p_.fx.assign(n, 0.0);
    p_.fy.assign(n, 0.0);
    p_.fz.assign(n, 0.0);
    if (p_.id.size() != n) {
      p_.id.resize(n);
      for (std::size_t i = 0; i < n; ++i) p_.id[i] = static_cast<Index>(i);
    }
    rotation_ = e.rotation;
    if (rotation_) {
      for (auto* v : {&p_.wx, &p_.wy, &p_.wz}) v->resize(n, 0.0);
      for (auto* v : {&p_.tx, &p_.ty, &p_.tz}) v->assign(n, 0.0);
      if (p_.inertia.size() != n) {
        p_.inertia.resize(n);
        for (std::size_t i = 0; i < n; ++i) p_.inertia[i] = 0.1 * p_.mass[i] * p_.diameter[i] * p_.diameter[i];  // solid sphere
      }
    }
    // Eq. 4-5: gravity m g and buoyancy -rho_f V g, folded into one factor
    // (1 - rho_f V / m) per particle; buoyancy only where there is a fluid.
    gravity_ = e.gravity ? scene.gravity : Vec3::Zero();
    buoyancy_density_ = (e.buoyancy && e.fluid) ? scene.fluid.density : 0.0;
    body_factor_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      body_factor_[i] = 1.0 - buoyancy_density_ * sphere_volume(p_.diameter[i]) / p_.mass[i];

    normal_contact_ = e.normal_contact;
    walls_ = e.walls;
    const ContactSpec& c = scene.contact;
    law_.normal_stiffness = c.normal_stiffness;
    law_.normal_damping = c.normal_damping;
    if (c.restitution) {
      const double log_e = std::log(*c.restitution);
      law_.damping_ratio = -log_e / std::sqrt(pi * pi + log_e * log_e);
    }
    law_.tangential_stiffness = c.tangential_stiffness;
    law_.tangential_damping = c.tangential_damping;
    law_.friction = c.friction;

    // Refuse an unstable step before any step is taken.
    if (normal_contact_ && n > 0) {
      const StabilityReport report = analyse_stability(c, e, mass_range(p_), dt_, walls_);
      require_stable_step(report, c, scene.source_file);
    }
    double d_max = 0.0;
    for (double d : p_.diameter) d_max = std::max(d_max, d);
    skin_ = 0.5 * d_max;
  }
  virtual ~Kernel() = default;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  void step() {
    if (frozen_) {
      time_ += dt_;
      ++steps_;
      return;
    }
    if (forces_stale_) {  // F^n for the first kick (start, after moves or a new external force)
      refresh_neighbours(true);
      compute_forces();
      forces_stale_ = false;
    }
    step_impl();
    time_ += dt_;
    ++steps_;
  }

  virtual DemDiagnostics diagnostics() const = 0;

  Particles p_;
  Box domain_;
  double dt_ = 0.0, time_ = 0.0, skin_ = 0.0;
  std::size_t steps_ = 0, removed_ = 0;
  bool rotation_ = false, walls_ = true, normal_contact_ = true;
  bool frozen_ = false, forces_stale_ = true;
  Vec3 gravity_ = Vec3::Zero();
  double buoyancy_density_ = 0.0;
  std::vector<double> body_factor_;
  ContactLaw law_;
  NeighbourList list_;
  ExternalForce* external_ = nullptr;

 protected:
  virtual void step_impl() = 0;
  virtual void compute_forces() = 0;
  virtual void refresh_neighbours(bool force) = 0;
};

namespace {

constexpr int kWalls = 6;
// Below this many particles a parallel region costs more than it saves (and
// on an oversubscribed machine a barrier can cost a whole time slice).
constexpr std::ptrdiff_t kParallelMin = 2500;  // x_min, x_max, y_min, y_max, z_min, z_max (scene FaceBoundary order)

template <bool Tangential, bool Rotation, bool Walls, bool DampingFromRestitution>
class KernelFor final : public DemEngine::Kernel {
 public:
  using Kernel::Kernel;

  void refresh_neighbours(bool force) override {
    const bool lost = remove_lost_particles();
    if (!normal_contact_) return;
    if (!(force || lost || list_.needs_rebuild(p_))) return;
    if constexpr (Tangential) {
      // Keep the slip history of pairs that stay in the list.
      const std::vector<Index> old_offsets = list_.offsets(), old_indices = list_.indices();
      const std::vector<Vec3> old_slip = std::move(slip_);
      list_.build(p_, skin_);
      slip_.assign(list_.entries(), Vec3::Zero());
      if (!old_offsets.empty()) {
        const auto n = static_cast<std::ptrdiff_t>(p_.size());
#pragma omp parallel for schedule(static) if (n > kParallelMin)
        for (std::ptrdiff_t si = 0; si < n; ++si) {
          const auto i = static_cast<std::size_t>(si);
          const auto oi = static_cast<std::size_t>(old_index(i));
          if (oi + 1 >= old_offsets.size()) continue;
          const auto ob = old_indices.begin() + old_offsets[oi], oe = old_indices.begin() + old_offsets[oi + 1];
          for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
            const Index oj = old_index(static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]));
            const auto it = std::lower_bound(ob, oe, oj);
            if (it != oe && *it == oj)
              slip_[static_cast<std::size_t>(k)] = old_slip[static_cast<std::size_t>(it - old_indices.begin())];
          }
        }
      }
      old_to_new_base_.clear();
    } else {
      list_.build(p_, skin_);
    }
  }

  DemDiagnostics diagnostics() const override {
    DemDiagnostics d;
    d.steps = steps_;
    d.particles = p_.size();
    d.particles_removed = removed_;
    d.neighbour_rebuilds = list_.builds();
    const std::size_t n = p_.size();
    for (std::size_t i = 0; i < n; ++i) {
      d.kinetic_energy_j += 0.5 * p_.mass[i] * (p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i] + p_.vz[i] * p_.vz[i]);
      if constexpr (Rotation)
        d.kinetic_energy_j += 0.5 * p_.inertia[i] * (p_.wx[i] * p_.wx[i] + p_.wy[i] * p_.wy[i] + p_.wz[i] * p_.wz[i]);
      if (normal_contact_ && list_.offsets().size() == n + 1) {
        for (Index j : list_.neighbours(i)) {
          const auto uj = static_cast<std::size_t>(j);
          if (uj <= i) continue;
          const double dx = p_.x[uj] - p_.x[i], dy = p_.y[uj] - p_.y[i], dz = p_.z[uj] - p_.z[i];
          const double overlap = 0.5 * (p_.diameter[i] + p_.diameter[uj]) - std::sqrt(dx * dx + dy * dy + dz * dz);
          if (overlap > 0.0) {
            ++d.contacts;
            d.max_overlap_over_diameter =
                std::max(d.max_overlap_over_diameter, overlap / std::min(p_.diameter[i], p_.diameter[uj]));
          }
        }
      }
      if (Walls && normal_contact_) {
        for (int w = 0; w < kWalls; ++w) {
          const double overlap = 0.5 * p_.diameter[i] - wall_distance(i, w);
          if (overlap > 0.0) {
            ++d.wall_contacts;
            d.max_overlap_over_diameter = std::max(d.max_overlap_over_diameter, overlap / p_.diameter[i]);
          }
        }
      }
    }
    return d;
  }

 protected:
  void step_impl() override {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const double half_dt = 0.5 * dt_, dt = dt_;
    // 1. First kick and drift: v^{n+1/2} = v^n + dt/2 F^n/m, x^{n+1} = x^n + dt v^{n+1/2}.
    //    The same pass measures the largest displacement since the last list
    //    build and counts particles that left the domain (one sweep, not three).
    const bool have_list = list_.reference_x().size() == p_.size();
    // Without a list (normal contact off) measure against zeros: unused, and
    // never aliasing the positions written below.
    if (!have_list) no_reference_.assign(p_.size(), 0.0);
    const double* __restrict x0 = have_list ? list_.reference_x().data() : no_reference_.data();
    const double* __restrict y0 = have_list ? list_.reference_y().data() : no_reference_.data();
    const double* __restrict z0 = have_list ? list_.reference_z().data() : no_reference_.data();
    const Vec3 lo = domain_.lower, hi = domain_.upper;
    double max_disp2 = 0.0;
    std::size_t outside = 0;
    // Raw restrict pointers: the arrays never alias, and saying so lets the
    // compiler vectorise this streaming loop (it is most of a free-fall step).
    double* __restrict x = p_.x.data();
    double* __restrict y = p_.y.data();
    double* __restrict z = p_.z.data();
    double* __restrict vx = p_.vx.data();
    double* __restrict vy = p_.vy.data();
    double* __restrict vz = p_.vz.data();
    const double* __restrict fx = p_.fx.data();
    const double* __restrict fy = p_.fy.data();
    const double* __restrict fz = p_.fz.data();
    const double* __restrict mass = p_.mass.data();
    const double lx = lo.x(), ly = lo.y(), lz = lo.z(), hx = hi.x(), hy = hi.y(), hz = hi.z();
#pragma omp parallel for simd schedule(static) if (n > kParallelMin) reduction(max : max_disp2) reduction(+ : outside)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const double a = half_dt / mass[i];
      const double vxi = vx[i] + a * fx[i], vyi = vy[i] + a * fy[i], vzi = vz[i] + a * fz[i];
      vx[i] = vxi;
      vy[i] = vyi;
      vz[i] = vzi;
      const double xi = x[i] + dt * vxi, yi = y[i] + dt * vyi, zi = z[i] + dt * vzi;
      x[i] = xi;
      y[i] = yi;
      z[i] = zi;
      const double dx = xi - x0[i], dy = yi - y0[i], dz = zi - z0[i];
      max_disp2 = std::max(max_disp2, dx * dx + dy * dy + dz * dz);
      const bool inside = (xi >= lx) & (xi <= hx) & (yi >= ly) & (yi <= hy) & (zi >= lz) & (zi <= hz);
      outside += inside ? 0u : 1u;
    }
    if constexpr (Rotation) {
#pragma omp parallel for schedule(static) if (n > kParallelMin)
      for (std::ptrdiff_t si = 0; si < n; ++si) {
        const auto i = static_cast<std::size_t>(si);
        const double b = half_dt / p_.inertia[i];
        p_.wx[i] += b * p_.tx[i];
        p_.wy[i] += b * p_.ty[i];
        p_.wz[i] += b * p_.tz[i];
      }
    }
    const bool domain_set = hi.x() > lo.x() && hi.y() > lo.y() && hi.z() > lo.z();
    const bool rebuild = !have_list || max_disp2 > 0.25 * list_.skin() * list_.skin() || (domain_set && outside > 0);
    // 2. Neighbours (rebuilt only past skin/2), then F^{n+1}(x^{n+1}, v^{n+1/2}).
    if (rebuild) refresh_neighbours(true);
    compute_forces();
    // 3. Second kick: v^{n+1} = v^{n+1/2} + dt/2 F^{n+1}/m.
    const auto m = static_cast<std::ptrdiff_t>(p_.size());
    {
      double* __restrict ux = p_.vx.data();
      double* __restrict uy = p_.vy.data();
      double* __restrict uz = p_.vz.data();
      const double* __restrict gx = p_.fx.data();
      const double* __restrict gy = p_.fy.data();
      const double* __restrict gz = p_.fz.data();
      const double* __restrict mm = p_.mass.data();
#pragma omp parallel for simd schedule(static) if (m > kParallelMin)
      for (std::ptrdiff_t i = 0; i < m; ++i) {
        const double a = half_dt / mm[i];
        ux[i] += a * gx[i];
        uy[i] += a * gy[i];
        uz[i] += a * gz[i];
      }
    }
    if constexpr (Rotation) {
#pragma omp parallel for schedule(static) if (m > kParallelMin)
      for (std::ptrdiff_t si = 0; si < m; ++si) {
        const auto i = static_cast<std::size_t>(si);
        const double b = half_dt / p_.inertia[i];
        p_.wx[i] += b * p_.tx[i];
        p_.wy[i] += b * p_.ty[i];
        p_.wz[i] += b * p_.tz[i];
      }
    }
  }

  void compute_forces() override {
    const auto n = static_cast<std::ptrdiff_t>(p_.size());
    const bool contacts = normal_contact_;
    // Each thread owns particle i and writes only i's force and torque
    // (full neighbour list): the sum over i's contacts runs in ascending j
    // whatever the thread count, so results are bit-identical for any count.
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::ptrdiff_t si = 0; si < n; ++si) {
      const auto i = static_cast<std::size_t>(si);
      const double bm = p_.mass[i] * body_factor_[i];  // Eq. 4-5
      Vec3 f(bm * gravity_.x(), bm * gravity_.y(), bm * gravity_.z());
      Vec3 torque = Vec3::Zero();
      if (contacts) {
        const double ri = 0.5 * p_.diameter[i];
        const Vec3 xi(p_.x[i], p_.y[i], p_.z[i]);
        const Vec3 vi(p_.vx[i], p_.vy[i], p_.vz[i]);
        for (Index k = list_.offsets()[i]; k < list_.offsets()[i + 1]; ++k) {
          const auto j = static_cast<std::size_t>(list_.indices()[static_cast<std::size_t>(k)]);
          const Vec3 dx = Vec3(p_.x[j], p_.y[j], p_.z[j]) - xi;
          const double rj = 0.5 * p_.diameter[j];
          const double sum_r = ri + rj;
          const double dist2 = dx.squaredNorm();
          // (A branch-free, masked version of this loop was measured 1.6-1.9x
          // slower on scene B: it pays sqrt and division for the ~60 % of
          // entries not in contact.)
          if (dist2 >= sum_r * sum_r) {
            if constexpr (Tangential) slip_[static_cast<std::size_t>(k)].setZero();  // contact ended: forget the slip
            continue;
          }
          const double dist = std::sqrt(dist2);
          const Vec3 nrm = dx / dist;  // from i towards j
          Vec3 v_rel = vi - Vec3(p_.vx[j], p_.vy[j], p_.vz[j]);
          if constexpr (Rotation) {
            // contact-point velocities: v_i + w_i x (r_i n) - v_j - w_j x (-r_j n); written so that the
            // j->i evaluation is the exact negative (Newton's third law bit for bit).
            const Vec3 spin = ri * Vec3(p_.wx[i], p_.wy[i], p_.wz[i]) + rj * Vec3(p_.wx[j], p_.wy[j], p_.wz[j]);
            v_rel += spin.cross(nrm);
          }
          const double m_eff = p_.mass[i] * p_.mass[j] / (p_.mass[i] + p_.mass[j]);
          Vec3* slip = nullptr;
          if constexpr (Tangential) slip = &slip_[static_cast<std::size_t>(k)];
          const ContactForce cf = contact_force<Tangential, DampingFromRestitution>(law_, m_eff, sum_r - dist, nrm,
                                                                                     v_rel, dt_, slip);
          f += cf.normal;
          if constexpr (Tangential) {
            f += cf.tangential;
            if constexpr (Rotation) torque += (ri * nrm).cross(cf.tangential);  // Eq. 10
          }
        }
        if constexpr (Walls) wall_forces(i, f, torque);
      }
      p_.fx[i] = f.x();
      p_.fy[i] = f.y();
      p_.fz[i] = f.z();
      if constexpr (Rotation) {
        p_.tx[i] = torque.x();
        p_.ty[i] = torque.y();
        p_.tz[i] = torque.z();
      }
    }
    if (external_ != nullptr) external_->add(p_, p_.fx, p_.fy, p_.fz);
  }

 private:
  double wall_distance(std::size_t i, int w) const {
    const int axis = w / 2;
    const double xi = axis == 0 ? p_.x[i] : axis == 1 ? p_.y[i] : p_.z[i];
    return (w % 2 == 0) ? xi - domain_.lower[axis] : domain_.upper[axis] - xi;
  }

  // The six box planes, at rest; particle-wall m_eff = m. Per axis two
  // gaps; the contact branch is rarely taken, so it predicts well.
  void wall_forces(std::size_t i, Vec3& f, Vec3& torque) {
    const double ri = 0.5 * p_.diameter[i];
    const double pos[3] = {p_.x[i], p_.y[i], p_.z[i]};
    for (int axis = 0; axis < 3; ++axis) {
      const double gap_lower = pos[axis] - domain_.lower[axis];
      const double gap_upper = domain_.upper[axis] - pos[axis];
      if (gap_lower < ri) [[unlikely]] wall_contact(i, 2 * axis, ri, gap_lower, f, torque);
      else if constexpr (Tangential) wall_slip_[kWalls * i + static_cast<std::size_t>(2 * axis)].setZero();
      if (gap_upper < ri) [[unlikely]] wall_contact(i, 2 * axis + 1, ri, gap_upper, f, torque);
      else if constexpr (Tangential) wall_slip_[kWalls * i + static_cast<std::size_t>(2 * axis + 1)].setZero();
    }
  }

  void wall_contact(std::size_t i, int w, double ri, double gap, Vec3& f, Vec3& torque) {
    Vec3 nrm = Vec3::Zero();  // from the sphere towards the wall
    nrm[w / 2] = (w % 2 == 0) ? -1.0 : 1.0;
    Vec3 v_rel(p_.vx[i], p_.vy[i], p_.vz[i]);
    if constexpr (Rotation) v_rel += (ri * Vec3(p_.wx[i], p_.wy[i], p_.wz[i])).cross(nrm);
    Vec3* slip = nullptr;
    if constexpr (Tangential) slip = &wall_slip_[kWalls * i + static_cast<std::size_t>(w)];
    const ContactForce cf =
        contact_force<Tangential, DampingFromRestitution>(law_, p_.mass[i], ri - gap, nrm, v_rel, dt_, slip);
    f += cf.normal;
    if constexpr (Tangential) {
      f += cf.tangential;
      if constexpr (Rotation) torque += (ri * nrm).cross(cf.tangential);  // Eq. 10
    }
  }

  Index old_index(std::size_t i) const {
    return old_to_new_base_.empty() ? static_cast<Index>(i) : old_to_new_base_[i];
  }

  // Removes particles whose centre left the domain box (lost: only an
  // exploding or escaping grain gets there). Keeps the order of the rest.
  bool remove_lost_particles() {
    const Vec3 lo = domain_.lower, hi = domain_.upper;
    if (!(hi.x() > lo.x() && hi.y() > lo.y() && hi.z() > lo.z())) return false;
    const std::size_t n = p_.size();
    auto outside = [&](std::size_t i) {
      return !(p_.x[i] >= lo.x() && p_.x[i] <= hi.x() && p_.y[i] >= lo.y() && p_.y[i] <= hi.y() &&
               p_.z[i] >= lo.z() && p_.z[i] <= hi.z());
    };
    std::size_t lost = 0;
    for (std::size_t i = 0; i < n; ++i) lost += outside(i) ? 1 : 0;
    if (lost == 0) return false;
    std::vector<Index> kept;
    kept.reserve(n - lost);
    for (std::size_t i = 0; i < n; ++i)
      if (!outside(i)) kept.push_back(static_cast<Index>(i));
    auto compact = [&](auto& v) {
      if (v.size() != n) return;
      for (std::size_t k = 0; k < kept.size(); ++k) v[k] = v[static_cast<std::size_t>(kept[k])];
      v.resize(kept.size());
    };
    for (auto* v : {&p_.x, &p_.y, &p_.z, &p_.vx, &p_.vy, &p_.vz, &p_.fx, &p_.fy, &p_.fz, &p_.diameter, &p_.mass,
                    &p_.wx, &p_.wy, &p_.wz, &p_.tx, &p_.ty, &p_.tz, &p_.inertia, &body_factor_})
      compact(*v);
    compact(p_.id);
    if constexpr (Tangential) {
      for (std::size_t k = 0; k < kept.size(); ++k)
        for (std::size_t w = 0; w < kWalls; ++w)
          wall_slip_[kWalls * k + w] = wall_slip_[kWalls * static_cast<std::size_t>(kept[k]) + w];
      wall_slip_.resize(kWalls * kept.size());
    }
    old_to_new_base_ = std::move(kept);  // new index -> old index, for the slip history transfer
    removed_ += lost;
    return true;
  }

 public:
  void init_storage() {
    if constexpr (Tangential) wall_slip_.assign(kWalls * p_.size(), Vec3::Zero());
    refresh_neighbours(true);  // F^0, so diagnostics and the first kick see the initial contacts
    compute_forces();
    forces_stale_ = false;
  }

 private:
  std::vector<Vec3> slip_;        // per neighbour-list entry (Tangential only)
  std::vector<Vec3> wall_slip_;   // per particle and wall (Tangential only)
  std::vector<Index> old_to_new_base_;  // after a removal: new index -> old index
  std::vector<double> no_reference_;    // zeros, when there is no neighbour list
};

template <bool T, bool R, bool W, bool D>
std::unique_ptr<DemEngine::Kernel> make(Particles&& p, const Scene& s) {
  auto k = std::make_unique<KernelFor<T, R, W, D>>(std::move(p), s);
  k->init_storage();
  return k;
}

// The one table of supported effect combinations, dispatched once.
std::unique_ptr<DemEngine::Kernel> make_kernel(Particles&& p, const Scene& s) {
  const Effects& e = s.effects;
  const bool t = e.tangential_contact && e.normal_contact, r = e.rotation, w = e.walls;
  const bool d = s.contact.restitution.has_value();
  const int key = (t ? 8 : 0) | (r ? 4 : 0) | (w ? 2 : 0) | (d ? 1 : 0);
  switch (key) {
    case 0: return make<false, false, false, false>(std::move(p), s);
    case 1: return make<false, false, false, true>(std::move(p), s);
    case 2: return make<false, false, true, false>(std::move(p), s);
    case 3: return make<false, false, true, true>(std::move(p), s);
    case 4: return make<false, true, false, false>(std::move(p), s);
    case 5: return make<false, true, false, true>(std::move(p), s);
    case 6: return make<false, true, true, false>(std::move(p), s);
    case 7: return make<false, true, true, true>(std::move(p), s);
    case 8: return make<true, false, false, false>(std::move(p), s);
    case 9: return make<true, false, false, true>(std::move(p), s);
    case 10: return make<true, false, true, false>(std::move(p), s);
    case 11: return make<true, false, true, true>(std::move(p), s);
    case 12: return make<true, true, false, false>(std::move(p), s);
    case 13: return make<true, true, false, true>(std::move(p), s);
    case 14: return make<true, true, true, false>(std::move(p), s);
    default: return make<true, true, true, true>(std::move(p), s);
  }
}

}  // namespace

DemEngine::DemEngine(Particles particles, const Scene& scene) : kernel_(make_kernel(std::move(particles), scene)) {}
DemEngine::~DemEngine() = default;
DemEngine::DemEngine(DemEngine&&) noexcept = default;
DemEngine& DemEngine::operator=(DemEngine&&) noexcept = default;

void DemEngine::step() { kernel_->step(); }
void DemEngine::run(std::size_t steps) {
  for (std::size_t s = 0; s < steps; ++s) kernel_->step();
}
double DemEngine::time() const { return kernel_->time_; }
double DemEngine::dem_step() const { return kernel_->dt_; }
Particles& DemEngine::particles() { return kernel_->p_; }
const Particles& DemEngine::particles() const { return kernel_->p_; }
void DemEngine::particles_moved() { kernel_->forces_stale_ = true; }
void DemEngine::set_external_force(ExternalForce* force) {
  kernel_->external_ = force;
  kernel_->forces_stale_ = true;
}
void DemEngine::set_frozen(bool frozen) {
  if (kernel_->frozen_ && !frozen) kernel_->forces_stale_ = true;
  kernel_->frozen_ = frozen;
}
bool DemEngine::frozen() const { return kernel_->frozen_; }
DemDiagnostics DemEngine::diagnostics() const { return kernel_->diagnostics(); }
void DemEngine::set_skin(double skin_m) {
  if (!(skin_m > 0.0)) throw std::invalid_argument("DemEngine::set_skin: skin must be positive");
  kernel_->skin_ = skin_m;
  kernel_->forces_stale_ = true;
}

}  // namespace fdem
