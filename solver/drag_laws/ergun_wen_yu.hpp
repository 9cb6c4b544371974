#pragma once
// The paper's drag (Sect. 2.1, Eq. 11-15): Ergun below eps = 0.8, Wen & Yu
// above, with the isolated-sphere Cd of Rowe & Henwood.
//
//   f_D = pi/6 d^3 beta / (1 - eps) (u - v)                          Eq. 11
//   beta = 150 (1-eps)^2 mu / (eps d^2) + 1.75 (1-eps) rho |u-v| / d,  eps < 0.8   Eq. 12 (Ergun)
//   beta = 3/4 Cd eps (1-eps) rho |u-v| / d * eps^-2.65,              eps >= 0.8  Eq. 13 (Wen & Yu)
//   Cd = 24/Re (1 + 0.15 Re^0.687) for Re <= 1000, 0.44 above        Eq. 14 (Rowe & Henwood)
//   Re = eps rho |u-v| d / mu                                         Eq. 15
//
// Eq. 12 is garbled in the paper's text extraction; the form coded is the
// standard one of Kuipers et al. (1992) and Gidaspow (1994, "Multiphase Flow
// and Fluidization", Eq. 5.67), which the paper cites as [24].
//
// Eq. 11 divides beta by (1 - eps), which is 0/0 for an isolated particle
// (eps = 1). Both closures carry a factor (1 - eps), cancelled analytically:
//   Ergun:    K = 150 (1-eps) mu / (eps d^2) + 1.75 rho |u-v| / d
//   Wen & Yu: K = 3/4 Cd eps rho |u-v| / d * eps^-2.65
// At eps = 1 Wen & Yu gives the isolated-sphere drag 1/2 Cd rho (pi d^2/4) |u-v| (u-v).
//
// The switch at eps = 0.8 is discontinuous. In the viscous limit (Re -> 0)
// K_Ergun / K_WenYu = (150 * 0.2 / 0.8) / (18 * 0.8^-2.65) = 37.5 / 32.52 =
// 1.153: the drag drops by 13 % when eps crosses 0.8 from below. At higher
// Re the ratio changes (1.33 at Re = 40, d = 0.5 mm; drag_jump_at_switch()).
// Cd of Eq. 14 is nearly continuous at Re = 1000: 0.4383 below, 0.44 above (0.4 %).
//
// Folded per step (a = eps rho d / mu, so Re = a s with s = |u - v|):
//   c = c0 + c1 s + c2 s^0.687                 (Re <= 1000)
//   c = c0 (0.44 / 24) a s                      (Re > 1000, Wen & Yu only)
//   Ergun (Eq. 12):    c0 = V_p 150 (1-eps) mu / (eps d^2), c1 = V_p 1.75 rho / d, c2 = 0, a = 0
//   Wen & Yu (13, 14): c0 = V_p 18 mu / d^2 eps^-2.65,       c1 = 0, c2 = 0.15 a^0.687 c0
// (Wen & Yu: Cd s = 24 mu / (eps rho d) (1 + 0.15 Re^0.687), finite at zero
// slip, gives c0 (1 + 0.15 a^0.687 s^0.687).) The subcycle then needs only
// the slip: s = sqrt(s^2) and s^0.687 = (s^2)^0.3435 (the same double
// exponent halved, an exact rewrite), the switch Re > 1000 tested as
// a^2 s^2 > 1e6; s only in a group where some lane is Ergun or above
// Re = 1000. In the subcycle kernel the power is evaluated in single
// precision (subcycle_coefficients; single_precision_power,
// vector_math.hpp: within 2e-7 of x^y, measured), and from one subcycle to
// the next a lane takes it from its last such power by a series while its
// s^2 stays within 4 % (3.4e-9 more), so the solver's drag is within
// 2.04e-7 of the law, far inside the three digits of its exponent and the
// fluid solve's 1e-8 residual; the single-precision power made the plume's
// subcycle 1.3x faster on AVX2 (2026-12-07), the series 1.11-1.14x on Zen 4
// (2026-12-08, benchmarks/README.md). The law as written
// (coefficient: references, tests, the semi-implicit exchange's frozen
// coefficients) keeps a double pow. Until 2026-12-07 both used fdlibm's
// double exp(0.3435 log s^2) written out, until 2026-12-04 libmvec's.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "drag_laws/vector_math.hpp"
#include "drag_laws/drag_law.hpp"
#include "core/types.hpp"

namespace fdem {

/// Porosity at which Eq. 12 hands over to Eq. 13.
inline constexpr double ergun_wen_yu_switch = 0.8;
/// Particle Reynolds number above which Cd is constant (Eq. 14).
inline constexpr double cd_constant_above_reynolds = 1000.0;

/// Eq. 14 (Rowe & Henwood), the isolated-sphere Cd of Wen & Yu. Re must be > 0.
inline double rowe_henwood_drag_coefficient(double reynolds) {
  if (reynolds > cd_constant_above_reynolds) return 0.44;              // Newton regime
  return 24.0 / reynolds * (1.0 + 0.15 * std::pow(reynolds, 0.687));  // Rowe & Henwood
}

struct ErgunWenYu {
  // k[0..3] = c0 [kg/s], c1 [kg/m], c2 [kg s^-0.313 m^-0.687], a [s/m] (header comment).
  static constexpr double reynolds_exponent = 0.687;                    // Eq. 14
  static constexpr double half_exponent = 0.5 * reynolds_exponent;      // exact: halving a double
  static constexpr double wen_yu_porosity_exponent = -2.65;             // Eq. 13
  static constexpr double newton_over_viscous = 0.44 / 24.0;            // Cd = 0.44 above Re = 1000
  static constexpr double newton_reynolds_squared = cd_constant_above_reynolds * cd_constant_above_reynolds;
  static constexpr std::int64_t newton_reynolds_squared_bits = std::bit_cast<std::int64_t>(newton_reynolds_squared);

  static void fold(const DragLanes& eps, const DragLanes& d, const FluidProperties& fluid, FoldedDrag& out) {
    const double mu = fluid.viscosity, rho = fluid.density;
    // Lanes without fluid get eps = 1, d = 1 for the powers (a harmless
    // argument) and zero coefficients.
    alignas(64) DragLanes ee, dd, a, eps_power, re_power;
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const bool fluid_here = eps[l] > 0.0;
      ee[l] = fluid_here ? eps[l] : 1.0;
      dd[l] = fluid_here ? d[l] : 1.0;
      a[l] = ee[l] * rho * dd[l] / mu;  // Re / s (Eq. 15)
    }
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) eps_power[l] = pow(ee[l], wen_yu_porosity_exponent);  // Eq. 13
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) re_power[l] = pow(a[l], reynolds_exponent);  // Eq. 14
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const bool fluid_here = eps[l] > 0.0;
      const double e = ee[l], di = dd[l];
      const double vp = pi / 6.0 * di * di * di;             // V_p (Eq. 11)
      const double viscous = vp * (18.0 * mu / (di * di));  // 3 pi mu d: Wen & Yu's Re -> 0 limit
      const double wen_yu_c0 = viscous * eps_power[l];      // Eq. 13 / (1 - eps)
      const double wen_yu_c2 = wen_yu_c0 * (0.15 * re_power[l]);
      const double ergun_c0 = vp * (150.0 * (1.0 - e) * mu / (e * di * di));  // Eq. 12 / (1 - eps)
      const double ergun_c1 = vp * (1.75 * rho / di);
      const bool wen_yu = fluid_here && e >= ergun_wen_yu_switch;
      const bool ergun = fluid_here && e < ergun_wen_yu_switch;
      out.k[0][l] = wen_yu ? wen_yu_c0 : ergun ? ergun_c0 : 0.0;
      out.k[1][l] = ergun ? ergun_c1 : 0.0;
      out.k[2][l] = wen_yu ? wen_yu_c2 : 0.0;
      out.k[3][l] = wen_yu ? a[l] : 0.0;
    }
  }

  /// The law as written, its power in double (libmvec's pow, within 4 ulp):
  /// the scalar force_coefficient (GSL references, reports, tests) and the
  /// semi-implicit exchange's once-a-step coefficients. Smooth in s, which
  /// the references' adaptive integrators need: a single-precision power
  /// is a staircase at 1e-7 that made GSL's rk8pd crawl (a settling test
  /// 30 s -> 258 s).
  static void coefficient(const FoldedDrag& f, const DragLanes& s2, DragLanes& c) {
    alignas(64) DragLanes power;
    reynolds_power(f, s2, power);
    combine(f, s2, power, c);
  }
  /// The subcycle's power from a lane's reference (subcycle_coefficients):
  /// (s^2)^0.3435 = P_ref (1 + x)^0.3435, x = s^2 / s^2_ref - 1, the
  /// binomial series to x^4 while |x| <= reference_reach. Its terms
  /// alternate for x > 0 and share one sign for x < 0, so it is off by at
  /// most |c5| |x|^5 / (1 - |x|) = 3.3e-9 at |x| = 0.04 (c5 = 0.0302).
  static constexpr double reference_reach = 0.04;
  static constexpr double reference_series_error = 3.4e-9;
  /// The series: (1 + x)^0.3435 to x^4.
  static double reference_series(double x) {
    constexpr double c1 = half_exponent, c2 = c1 * (half_exponent - 1.0) / 2.0;
    constexpr double c3 = c2 * (half_exponent - 2.0) / 3.0, c4 = c3 * (half_exponent - 3.0) / 4.0;
    return 1.0 + x * (c1 + x * (c2 + x * (c3 + x * c4)));
  }
  /// How far subcycle_coefficients' c may be from coefficient()'s: the
  /// power's error, which c2 s^0.687 carries and c0 does not add to: the
  /// reference's single-precision power times the series, and a few
  /// roundings of 1e-16.
  static constexpr double subcycle_error =
      (1.0 + single_precision_power_error) * (1.0 + reference_series_error) - 1.0 + 1e-15;
  /// The subcycle kernel's (drag_kernel.hpp), a group of blocks at once,
  /// s^0.687 within 2.04e-7 of coefficient()'s (test_drag.cpp bounds it).
  /// Over a fluid step a grain's slip changes little from one subcycle to
  /// the next, so each lane keeps a reference, 1 / s^2 and (s^2)^0.3435
  /// of the last subcycle it took the power in single precision
  /// (DragBlock::memory, zero at the step's start), and takes its power
  /// from it by the series while s^2 stays within 4 % of it: in the
  /// plume's checkpoints (0.2, 0.5 and 0.9 s, 3000 subcycles each) 98.4-98.7
  /// % of the 16-lane vectors had every lane within reach (94-96 % at 1 %).
  /// Each lane's choice is its own, so its bits do not depend on the
  /// other lanes, the block or the thread. The single-precision power
  /// then runs only for blocks with a lane out of reach: for a whole group
  /// in one tight loop when more than a quarter of its blocks need it (the
  /// step's first subcycle), where the core overlaps successive vectors'
  /// polynomial chains (~100 cycles deep each; block by block it took 2.5x
  /// as long, 2026-12-07), else block by block.
  static void subcycle_coefficients(DragBlock* blocks, std::size_t count, const DragGroupLanes& s2,
                                    DragGroupLanes& c) {
    alignas(64) DragGroupLanes power, s;
    alignas(64) std::array<std::array<std::uint64_t, drag_block_size>, drag_group_size> out_of_reach;
    // Per-lane flags, reduced once a group (a reduction a block cost more
    // than the series: perf, 2026-12-08).
    alignas(64) std::array<std::uint64_t, drag_block_size> any_out{}, any_speed{};
    // 1. Every lane's power from its reference (zero where there is none:
    //    no Wen & Yu lane, c2 = 0, ever has one), which lanes are out of its
    //    reach, and which need the slip speed itself (Ergun, or Wen & Yu
    //    above Re = 1000).
    for (std::size_t q = 0; q < count; ++q) {
      const auto &inverse = blocks[q].memory[0], &reference = blocks[q].memory[1];
      const DragLanes &ergun = blocks[q].folded.k[1], &wen_yu = blocks[q].folded.k[2], &a = blocks[q].folded.k[3];
#pragma omp simd
      for (std::size_t l = 0; l < drag_block_size; ++l) {
        const double x = s2[q][l] * static_cast<double>(inverse[l]) - 1.0;
        power[q][l] = static_cast<double>(reference[l]) * reference_series(x);
        out_of_reach[q][l] = static_cast<std::uint64_t>(wen_yu[l] != 0.0) &
                             static_cast<std::uint64_t>(!(std::abs(x) <= reference_reach));
        any_out[l] |= out_of_reach[q][l];
        any_speed[l] |= speed_needed_in(ergun[l], a[l], s2[q][l]);
      }
    }
    std::uint64_t stale = 0, speed_needed = 0;
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      stale |= any_out[l];
      speed_needed |= any_speed[l];
    }
    // 2. The single-precision power where a lane is out of reach, which
    //    becomes its reference.
    if (stale != 0) renew_references(blocks, count, s2, out_of_reach, power);
    // 3. s = |u - v| only when a lane needs it (a dilute cloud, all Wen & Yu
    //    below Re = 1000, never does); the lanes that need no speed multiply
    //    it by zero, so skipping it changes nothing.
    if (speed_needed != 0) {
      const double* __restrict s2_lanes = s2[0].data();
      double* __restrict s_lanes = s[0].data();
      for (std::size_t l = 0; l < count * drag_block_size; ++l) s_lanes[l] = std::sqrt(s2_lanes[l]);
    } else {
      for (std::size_t q = 0; q < count; ++q) s[q].fill(0.0);
    }
    for (std::size_t q = 0; q < count; ++q) combine_lanes(blocks[q].folded, s2[q], s[q], power[q], c[q]);
  }

  /// subcycle_coefficients' step 2: the lanes out of reach take the power
  /// in single precision, and keep it with 1 / s^2 as their reference.
  static void renew_references(DragBlock* blocks, std::size_t count, const DragGroupLanes& s2,
                               const std::array<std::array<std::uint64_t, drag_block_size>, drag_group_size>& out,
                               DragGroupLanes& power) {
    std::array<bool, drag_group_size> stale{};
    std::size_t stale_blocks = 0;
    for (std::size_t q = 0; q < count; ++q) {
      for (std::size_t l = 0; l < drag_block_size; ++l) stale[q] = stale[q] || out[q][l] != 0;
      stale_blocks += stale[q] ? 1 : 0;
    }
    alignas(64) DragGroupLanes exact;
    if (4 * stale_blocks > count) {  // one flat loop over the group's lanes (the blocks lie end to end)
      const double* __restrict s2_lanes = s2[0].data();
      double* __restrict exact_lanes = exact[0].data();
      const std::size_t lanes = count * drag_block_size;
#pragma omp simd
      for (std::size_t l = 0; l < lanes; ++l) exact_lanes[l] = single_precision_power(s2_lanes[l], half_exponent);
    } else {
      for (std::size_t q = 0; q < count; ++q) {
        if (!stale[q]) continue;
#pragma omp simd
        for (std::size_t l = 0; l < drag_block_size; ++l) exact[q][l] = single_precision_power(s2[q][l], half_exponent);
      }
    }
    for (std::size_t q = 0; q < count; ++q) {
      if (!stale[q]) continue;
      auto &inverse = blocks[q].memory[0], &reference = blocks[q].memory[1];
      for (std::size_t l = 0; l < drag_block_size; ++l) {
        if (out[q][l] == 0) continue;
        power[q][l] = exact[q][l];
        // No slip: no reference (x = -1 next time); a float's range covers 1 / s^2 (its test).
        inverse[l] = s2[q][l] > 0.0 ? static_cast<float>(1.0 / s2[q][l]) : 0.0f;
        reference[l] = static_cast<float>(exact[q][l]);  // exact: a float's power
      }
    }
  }

  /// Whether a block has Wen & Yu lanes (c2 != 0), which need the power.
  static bool power_needed(const FoldedDrag& f) {
    const DragLanes& c2 = f.k[2];
    std::uint64_t needed = 0;  // 64-bit flags: no narrowing of the lane masks
#pragma omp simd reduction(| : needed)
    for (std::size_t l = 0; l < drag_block_size; ++l) needed |= static_cast<std::uint64_t>(c2[l] != 0.0);
    return needed != 0;
  }

  /// s^0.687 = (s^2)^0.3435 in double (libmvec's pow), zero in a block
  /// without Wen & Yu lanes (a packed bed: all Ergun), where c2 = 0 and it
  /// is not computed.
  static void reynolds_power(const FoldedDrag& f, const DragLanes& s2, DragLanes& power) {
    if (!power_needed(f)) {
      power.fill(0.0);
      return;
    }
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) power[l] = pow(s2[l], half_exponent);
  }

  /// 1 where a lane needs the slip speed itself: Ergun (c1 != 0), or Wen &
  /// Yu above Re = 1000 (a^2 s^2 > 1e6).
  static std::uint64_t speed_needed_in(double c1, double a, double s2) {
    return static_cast<std::uint64_t>(c1 != 0.0) | static_cast<std::uint64_t>(a * a * s2 > newton_reynolds_squared);
  }

  /// c from the squared slip and the block's s^0.687 (reynolds_power).
  static void combine(const FoldedDrag& f, const DragLanes& s2, const DragLanes& power, DragLanes& c) {
    const DragLanes &c1 = f.k[1], &a = f.k[3];
    // 1. Whether a lane needs the slip speed itself (Ergun, or Wen & Yu
    //    above Re = 1000).
    std::uint64_t speed_needed = 0;
#pragma omp simd reduction(| : speed_needed)
    for (std::size_t l = 0; l < drag_block_size; ++l) speed_needed |= speed_needed_in(c1[l], a[l], s2[l]);
    // 2. s = |u - v| only when needed (a dilute cloud, all Wen & Yu below
    //    Re = 1000, never needs it). The lanes that need no speed multiply
    //    it by zero, so skipping it changes nothing.
    alignas(64) DragLanes s;
    if (speed_needed != 0) {
      for (std::size_t l = 0; l < drag_block_size; ++l) s[l] = std::sqrt(s2[l]);
    } else {
      s.fill(0.0);
    }
    combine_lanes(f, s2, s, power, c);
  }

  /// Eq. 11-15 with the frozen factors folded, from the squared slip, the
  /// slip (or zero where no lane needs it) and s^0.687. Re^2 > 1e6 compared
  /// as the bits of the non-negative doubles (their order) and the select as
  /// a bit mask: GCC if-converts no floating-point compare or conditional
  /// multiply under -ftrapping-math for AVX2 (no masked operations), which
  /// left this loop scalar there.
  static void combine_lanes(const FoldedDrag& f, const DragLanes& s2, const DragLanes& s, const DragLanes& power,
                            DragLanes& c) {
    const DragLanes &c0 = f.k[0], &c1 = f.k[1], &c2 = f.k[2], &a = f.k[3];
#pragma omp simd
    for (std::size_t l = 0; l < drag_block_size; ++l) {
      const double regular = c0[l] + c1[l] * s[l] + c2[l] * power[l];
      const double newton = c0[l] * newton_over_viscous * a[l] * s[l];
      const std::uint64_t above =
          -static_cast<std::uint64_t>(std::bit_cast<std::int64_t>(a[l] * a[l] * s2[l]) > newton_reynolds_squared_bits);
      c[l] = std::bit_cast<double>((std::bit_cast<std::uint64_t>(newton) & above) |
                                   (std::bit_cast<std::uint64_t>(regular) & ~above));
    }
  }
};

}  // namespace fdem
