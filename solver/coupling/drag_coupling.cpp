#include "coupling/drag_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

// glibc declares the vector variants of its libm functions (libmvec,
// _ZGV<isa>N<lanes>v_log, ...) to GCC only under -ffast-math
// (bits/math-vector.h). We want them without fast-math's other licences
// (reassociation, finite-only arithmetic, flush to zero), so we make the
// same declarations glibc makes: `omp simd` loops calling pow, exp or log
// then call the 2/4/8-wide libmvec variant of the target (AVX-512:
// _ZGVeN8v_log, _ZGVeN8v_exp, _ZGVeN8vv_pow; <= 4 ulp by glibc's tables,
// measured <= 3 ulp for exp(0.3435 log x)); libm.so links libmvec as
// needed. Elsewhere (clang, other libcs) they stay the scalar libm calls.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) && !defined(__FAST_MATH__)
extern "C" {
__attribute__((__simd__("notinbranch"))) double pow(double, double) noexcept;
__attribute__((__simd__("notinbranch"))) double exp(double) noexcept;
__attribute__((__simd__("notinbranch"))) double log(double) noexcept;
}
#endif

namespace fdem {

namespace {

constexpr std::size_t kBlock = DragCoupling::block_size;

// Eq. 14: Re^0.687 with Re = a s is a^0.687 (s^2)^kHalfExponent.
constexpr double kReynoldsExponent = 0.687;
constexpr double kHalfExponent = 0.5 * kReynoldsExponent;  // exact: halving a double
constexpr double kWenYuPorosityExponent = -2.65;           // Eq. 13
// Above Re = 1000, Cd = 0.44 (Eq. 14): c = c0 (0.44 / 24) a s.
constexpr double kNewtonOverViscous = 0.44 / 24.0;
constexpr double kNewtonReynoldsSquared = cd_constant_above_reynolds * cd_constant_above_reynolds;

using Clock = std::chrono::steady_clock;

}  // namespace

DragCoupling::DragCoupling(DragLaw law, FluidProperties fluid, bool apply_to_particles)
    : law_(law), fluid_(fluid), apply_(apply_to_particles) {}

// Once per fluid step (and again if the DEM removes particles mid-step): the
// fluid velocity at each particle, then the coefficients of the header
// comment from its element's porosity and its diameter.
void DragCoupling::prepare(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles) {
  const std::size_t n = mapping.element.size();
  particles_ = n;
  blocks_.resize((n + kBlock - 1) / kBlock);
  const double mu = fluid_.viscosity, rho = fluid_.density;
  const double volume_factor = pi / 6.0;
  const bool wen_yu_possible = law_ == DragLaw::ergun_wen_yu;
  const auto nb = static_cast<std::ptrdiff_t>(blocks_.size());
#pragma omp parallel for schedule(static) if (nb > 512)
  for (std::ptrdiff_t b = 0; b < nb; ++b) {
    Block& blk = blocks_[static_cast<std::size_t>(b)];
    const std::size_t base = static_cast<std::size_t>(b) * kBlock;
    const std::size_t m = std::min(kBlock, n - base);
    alignas(64) std::array<double, kBlock> eps{}, d{};
    for (std::size_t l = 0; l < kBlock; ++l) blk.ux[l] = blk.uy[l] = blk.uz[l] = 0.0;
    for (std::size_t l = 0; l < m; ++l) {
      const std::size_t i = base + l;
      const Index e = mapping.element[i];
      d[l] = particles.diameter[i];
      if (e < 0) continue;  // outside the mesh: no fluid, no drag (eps = 0 marks it)
      const auto& nodes = mesh.element_nodes(e);
      const auto& w = mapping.weights[i];
      double u[3] = {0.0, 0.0, 0.0};
      for (std::size_t k = 0; k < 4; ++k) {  // P1 shape functions = volume coordinates (Eq. 28-31)
        const auto node = 3 * static_cast<std::size_t>(nodes[k]);
        for (std::size_t c = 0; c < 3; ++c) u[c] += w[k] * nodal_velocity_[node + c];
      }
      blk.ux[l] = u[0];
      blk.uy[l] = u[1];
      blk.uz[l] = u[2];
      eps[l] = porosity_[static_cast<std::size_t>(e)];
    }
    // Lanes without drag (outside, padding) get eps = 0 and zero
    // coefficients; the powers see a harmless argument there.
    alignas(64) std::array<double, kBlock> ee, dd, a, eps_power, re_power;
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) {
      const bool fluid_here = eps[l] > 0.0;
      ee[l] = fluid_here ? eps[l] : 1.0;
      dd[l] = fluid_here ? d[l] : 1.0;
      a[l] = ee[l] * rho * dd[l] / mu;  // Re / s (Eq. 15)
    }
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) eps_power[l] = pow(ee[l], kWenYuPorosityExponent);  // Eq. 13
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) re_power[l] = pow(a[l], kReynoldsExponent);  // Eq. 14
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) {
      const bool fluid_here = eps[l] > 0.0;
      const double e = ee[l], di = dd[l];
      const double vp = volume_factor * di * di * di;      // V_p (Eq. 11)
      const double viscous = vp * (18.0 * mu / (di * di));  // 3 pi mu d: Stokes, and Wen & Yu's Re -> 0 limit
      const double wen_yu_c0 = viscous * eps_power[l];      // Eq. 13 / (1 - eps)
      const double wen_yu_c2 = wen_yu_c0 * (0.15 * re_power[l]);
      const double ergun_c0 = vp * (150.0 * (1.0 - e) * mu / (e * di * di));  // Eq. 12 / (1 - eps)
      const double ergun_c1 = vp * (1.75 * rho / di);
      const bool wen_yu = fluid_here && wen_yu_possible && e >= ergun_wen_yu_switch;
      const bool ergun = fluid_here && wen_yu_possible && e < ergun_wen_yu_switch;
      blk.c0[l] = wen_yu ? wen_yu_c0 : ergun ? ergun_c0 : fluid_here ? viscous : 0.0;
      blk.c1[l] = ergun ? ergun_c1 : 0.0;
      blk.c2[l] = wen_yu ? wen_yu_c2 : 0.0;
      blk.a[l] = wen_yu ? a[l] : 0.0;
      blk.sum_x[l] = blk.sum_y[l] = blk.sum_z[l] = 0.0;
    }
  }
  mean_x_.assign(n, 0.0);
  mean_y_.assign(n, 0.0);
  mean_z_.assign(n, 0.0);
  evaluations_ = 0;
}

void DragCoupling::begin_step(const BoxMesh& mesh, const ParticleMapping& mapping, const Particles& particles,
                              std::span<const double> fluid_velocity, std::span<const double> porosity) {
  mesh_ = &mesh;
  nodal_velocity_ = fluid_velocity;
  porosity_ = porosity;
  prepare(mesh, mapping, particles);
  remapped_ = false;
  evaluation_seconds_ = 0.0;
}

void DragCoupling::add(const Particles& p, std::span<double> fx, std::span<double> fy, std::span<double> fz) {
  const auto t0 = Clock::now();
  if (p.size() != particles_) {
    // The DEM removed particles mid-step: indices shifted. Map the survivors
    // again (the porosity stays that of the step start) and restart the sums.
    own_mapping_.update(*mesh_, p);
    prepare(*mesh_, own_mapping_, p);
    remapped_ = true;
  }
  const std::size_t n = particles_;
  const auto nb = static_cast<std::ptrdiff_t>(blocks_.size());
  const bool apply = apply_;
#pragma omp parallel for schedule(static) if (nb > 256)
  for (std::ptrdiff_t b = 0; b < nb; ++b) {
    Block& blk = blocks_[static_cast<std::size_t>(b)];
    const std::size_t base = static_cast<std::size_t>(b) * kBlock;
    const std::size_t m = std::min(kBlock, n - base);
    alignas(64) std::array<double, kBlock> vx{}, vy{}, vz{}, sx, sy, sz, s2, s{}, power{}, gx, gy, gz;
    if (m == kBlock) {  // all blocks but possibly the last: a fixed-size copy the compiler vectorises
      for (std::size_t l = 0; l < kBlock; ++l) {
        vx[l] = p.vx[base + l];
        vy[l] = p.vy[base + l];
        vz[l] = p.vz[base + l];
      }
    } else {
      for (std::size_t l = 0; l < m; ++l) {
        vx[l] = p.vx[base + l];
        vy[l] = p.vy[base + l];
        vz[l] = p.vz[base + l];
      }
    }
    // 1. Slip u - v and its square; whether a lane needs the slip speed
    //    itself (Ergun, or Wen & Yu above Re = 1000: a^2 s^2 > 1000^2) and
    //    whether one needs the power (Wen & Yu).
    int speed_needed = 0, power_needed = 0;
#pragma omp simd reduction(| : speed_needed, power_needed)
    for (std::size_t l = 0; l < kBlock; ++l) {
      sx[l] = blk.ux[l] - vx[l];
      sy[l] = blk.uy[l] - vy[l];
      sz[l] = blk.uz[l] - vz[l];
      s2[l] = sx[l] * sx[l] + sy[l] * sy[l] + sz[l] * sz[l];
      const bool newton = blk.a[l] * blk.a[l] * s2[l] > kNewtonReynoldsSquared;
      speed_needed |= static_cast<int>(blk.c1[l] != 0.0) | static_cast<int>(newton);
      power_needed |= static_cast<int>(blk.c2[l] != 0.0);
    }
    // 2. s = |u - v| only when needed (a dilute cloud, all Wen & Yu below
    //    Re = 1000, never needs it). Scalar: GCC's sqrt may set errno
    //    (-fmath-errno), which keeps it out of vector loops; the lanes that
    //    need no speed multiply it by zero, so skipping it changes nothing.
    if (speed_needed != 0)
      for (std::size_t l = 0; l < kBlock; ++l) s[l] = std::sqrt(s2[l]);
    // 3. s^0.687 = (s^2)^0.3435 = exp(0.3435 log s^2): still a power, but
    //    libmvec's vector exp and log take 0.6x the time of its vector pow
    //    (measured, AVX-512, 28224 lanes), at <= 3 ulp. Skipped in a block
    //    without Wen & Yu lanes (a packed bed: all Ergun), where c2 = 0.
    if (power_needed != 0) {
#pragma omp simd
      for (std::size_t l = 0; l < kBlock; ++l) power[l] = exp(kHalfExponent * log(s2[l]));
    }
    // 4. Eq. 11-15 with the frozen factors folded (header comment).
#pragma omp simd
    for (std::size_t l = 0; l < kBlock; ++l) {
      const double a = blk.a[l];
      const double regular = blk.c0[l] + blk.c1[l] * s[l] + blk.c2[l] * power[l];
      const double newton = blk.c0[l] * kNewtonOverViscous * a * s[l];
      const double c = a * a * s2[l] > kNewtonReynoldsSquared ? newton : regular;
      gx[l] = c * sx[l];
      gy[l] = c * sy[l];
      gz[l] = c * sz[l];
      blk.sum_x[l] += gx[l];
      blk.sum_y[l] += gy[l];
      blk.sum_z[l] += gz[l];
    }
    if (apply && m == kBlock) {
      for (std::size_t l = 0; l < kBlock; ++l) {
        fx[base + l] += gx[l];
        fy[base + l] += gy[l];
        fz[base + l] += gz[l];
      }
    } else if (apply) {
      for (std::size_t l = 0; l < m; ++l) {
        fx[base + l] += gx[l];
        fy[base + l] += gy[l];
        fz[base + l] += gz[l];
      }
    }
  }
  ++evaluations_;
  evaluation_seconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
}

void DragCoupling::end_step() {
  if (evaluations_ == 0) return;
  const double inv = 1.0 / static_cast<double>(evaluations_);
  for (std::size_t i = 0; i < particles_; ++i) {
    const Block& blk = blocks_[i / kBlock];
    const std::size_t l = i % kBlock;
    mean_x_[i] = blk.sum_x[l] * inv;
    mean_y_[i] = blk.sum_y[l] * inv;
    mean_z_[i] = blk.sum_z[l] * inv;
  }
}

Vec3 DragCoupling::total_mean_drag() const {
  Vec3 total = Vec3::Zero();
  for (std::size_t i = 0; i < mean_x_.size(); ++i) total += Vec3(mean_x_[i], mean_y_[i], mean_z_[i]);
  return total;
}

}  // namespace fdem
