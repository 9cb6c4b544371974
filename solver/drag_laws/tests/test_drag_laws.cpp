// The registered drag laws (drag_laws/) against values computed by
// hand from each paper's formula, independently of the code path: the slip
// that gives the chosen Re, then the paper's expressions step by step
// (intermediate values in the comments, 7 significant digits). d = 0.5 mm
// in water (rho 1000 kg/m^3, mu 1e-3 Pa s), Re = eps rho |u-v| d / mu, so
// |u-v| = Re mu / (eps rho d).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include "coupling/drag.hpp"
#include "drag_laws/drag_law.hpp"
#include "drag_laws/ergun_wen_yu.hpp"
#include "drag_laws/vector_math.hpp"

namespace fdem {
namespace {

const FluidProperties water{1000.0, 1.0e-3};
constexpr double kDiameter = 5e-4;
// Hand values are rounded to 7 significant digits: compare at 1e-6 relative.
constexpr double kHandRounding = 1e-6;

double slip_for(double eps, double reynolds) { return reynolds * water.viscosity / (eps * water.density * kDiameter); }

struct HandValue {
  double porosity, reynolds, force_coefficient;  // K [kg/(m^3 s)]
};

void expect_law_matches(const char* name, std::initializer_list<HandValue> values) {
  const DragLawEntry& law = drag_law(name);
  for (const HandValue& h : values) {
    const double k = force_coefficient(law, h.porosity, slip_for(h.porosity, h.reynolds), kDiameter, water);
    EXPECT_NEAR(k, h.force_coefficient, h.force_coefficient * kHandRounding)
        << name << " eps " << h.porosity << " Re " << h.reynolds;
  }
}

TEST(DragLaws, DiFelice1994MatchesHandComputation) {
  // K = 3/4 Cd0 rho |u-v| eps^(2-chi) / d, Cd0 = (0.63 + 4.8/sqrt(Re))^2,
  // chi = 3.7 - 0.65 exp(-(1.5 - log10 Re)^2 / 2).
  // eps 0.4, Re 1:   s 0.005,     Cd0 29.48490, chi 3.488976, eps^(2-chi) 3.913119 -> K 865334.5
  // eps 0.6, Re 20:  s 0.0666667, Cd0 2.901274, chi 3.062740, eps^(2-chi) 1.720947 -> K 499293.9
  // eps 0.9, Re 300: s 0.6666667, Cd0 0.8228814, chi 3.296737, eps^(2-chi) 1.146398 -> K 943349.6
  expect_law_matches("di_felice", {{0.4, 1.0, 865334.5}, {0.6, 20.0, 499293.9}, {0.9, 300.0, 943349.6}});
}

TEST(DragLaws, Rong2013MatchesHandComputation) {
  // Di Felice's K with chi = 2.65 (eps + 1) - (5.3 - 3.5 eps) eps^2 exp(-(1.5 - log10 Re)^2 / 2).
  // eps 0.4, Re 1:   chi 3.507417, eps^(2-chi) 3.979802 -> K 880080.5
  // eps 0.6, Re 20:  chi 3.110579, eps^(2-chi) 1.763521 -> K 511645.7
  // eps 0.9, Re 300: chi 3.954565, eps^(2-chi) 1.228672 -> K 1011051
  expect_law_matches("rong", {{0.4, 1.0, 880080.5}, {0.6, 20.0, 511645.7}, {0.9, 300.0, 1011051.0}});
}

TEST(DragLaws, Beetstra2007MatchesHandComputation) {
  // K = 18 mu eps F / d^2, F = 10 phi/eps^2 + eps^2 (1 + 1.5 sqrt(phi))
  //   + 0.413 Re / (24 eps^2) (1/eps + 3 phi eps + 8.4 Re^-0.343) / (1 + 10^(3 phi) Re^-(1+4 phi)/2).
  // eps 0.4, Re 1:   F0 37.84590, F1 0.01949826, F 37.86540 -> K 1090524
  // eps 0.6, Re 20:  F0 11.81264, F1 3.898188,   F 15.71083 -> K 678707.7
  // eps 0.9, Re 300: F0 2.428785, F1 15.78953,   F 18.21832 -> K 1180547
  expect_law_matches("beetstra", {{0.4, 1.0, 1090524.0}, {0.6, 20.0, 678707.7}, {0.9, 300.0, 1180547.0}});
}

TEST(DragLaws, BeetstraIsStokesForAnIsolatedSphereInCreepingFlow) {
  // eps = 1 (phi = 0): F = 1 + 0.413 Re / 24 (1 + 8.4 Re^-0.343) / (1 + Re^-0.5) -> 1 + O(Re^1.157).
  const double k = force_coefficient(drag_law("beetstra"), 1.0, slip_for(1.0, 1e-8), kDiameter, water);
  EXPECT_NEAR(k, 18.0 * water.viscosity / (kDiameter * kDiameter), 72.0 * 1e-7);
}

TEST(DragLaws, VoidageFunctionLawsReduceToDallavalleAtPorosityOne) {
  // eps = 1: eps^(2-chi) = 1 whatever chi, so K = 3/4 Cd0 rho s / d with
  // Cd0 = (0.63 + 4.8/sqrt(Re))^2. Re = 50: Cd0 = (0.63 + 0.6788225)^2 = 1.713016;
  // s = 0.1 m/s: K = 0.75 * 1.713016 * 1000 * 0.1 / 5e-4 = 256952.5.
  for (const char* name : {"di_felice", "rong"})
    EXPECT_NEAR(force_coefficient(drag_law(name), 1.0, 0.1, kDiameter, water), 256952.5, 256952.5 * kHandRounding)
        << name;
}

TEST(DragLaws, EveryLawIsFiniteAtZeroSlipAndPositiveElsewhere) {
  for (const DragLawEntry& law : drag_laws())
    for (double eps : {0.3, 0.8, 1.0})
      for (double s : {0.0, 1e-7, 0.05, 3.0}) {
        const double k = force_coefficient(law, eps, s, kDiameter, water);
        EXPECT_TRUE(std::isfinite(k)) << law.name << " eps " << eps << " s " << s;
        EXPECT_GT(k, 0.0) << law.name << " eps " << eps << " s " << s;
      }
}

// The subcycle's single-precision power (Ergun / Wen & Yu's s^0.687 =
// (s^2)^0.3435) against the double pow: within 2e-7 relative over far
// more than the slips a grain can have (x = s^2 from 1e-30 to 1e30; the
// worst of these 6e5 samples is 1.4e-7, two float ulp), with no growth
// in |y log x| (t's integer part is carried exactly); 0 and x below
// float's smallest normal give 0, 1 gives 1, and exact powers of two stay exact.
TEST(DragLaws, SinglePrecisionPowerIsWithinTwoTenMillionthsOfPow) {
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> log_x(std::log(1e-30), std::log(1e30));
  double worst = 0.0;
  for (const double y : {0.3435, 0.687, -0.3435}) {
    for (int i = 0; i < 200000; ++i) {
      const double x = std::exp(log_x(rng));
      const double reference = std::pow(x, y);
      worst = std::max(worst, std::abs(single_precision_power(x, y) - reference) / reference);
    }
  }
  EXPECT_LE(worst, single_precision_power_error);
  EXPECT_GT(worst, 1e-9);  // it is single precision: a double-exact result would mean the test measures nothing
  EXPECT_EQ(single_precision_power(0.0, 0.3435), 0.0);
  EXPECT_EQ(single_precision_power(1e-39, 0.3435), 0.0);
  EXPECT_EQ(single_precision_power(1.0, 0.3435), 1.0);
  EXPECT_EQ(single_precision_power(4.0, 0.5), 2.0);
}

// Wen & Yu's subcycle power from a lane's reference (ergun_wen_yu.hpp):
// the binomial series of (1 + x)^0.3435 to x^4 is within its stated
// bound (|c5| |x|^5 / (1 - |x|), 3.3e-9) over the reach it is used in, and
// the bound is the reach's: at twice the reach the series is off by ~2^5 = 32x more (27x).
TEST(DragLaws, WenYuReferenceSeriesIsWithinItsBoundOverItsReach) {
  constexpr double reach = ErgunWenYu::reference_reach;
  double worst = 0.0;
  for (int k = -4000; k <= 4000; ++k) {
    const double x = reach * k / 4000.0;
    const double exact = std::pow(1.0 + x, ErgunWenYu::half_exponent);
    worst = std::max(worst, std::abs(ErgunWenYu::reference_series(x) - exact) / exact);
  }
  EXPECT_LE(worst, ErgunWenYu::reference_series_error);
  EXPECT_GT(worst, 0.5 * ErgunWenYu::reference_series_error);  // the bound is tight, not a guess
  const double beyond = 2.0 * reach;
  const double exact = std::pow(1.0 + beyond, ErgunWenYu::half_exponent);
  EXPECT_GT(std::abs(ErgunWenYu::reference_series(beyond) - exact) / exact, 20.0 * ErgunWenYu::reference_series_error);
}

TEST(DragLaws, TableHoldsEachNameOnceWithADocLine) {
  std::set<std::string> names;
  for (const DragLawEntry& law : drag_laws()) {
    EXPECT_TRUE(names.insert(std::string(law.name)).second) << law.name;
    EXPECT_FALSE(law.doc.empty()) << law.name;
    EXPECT_EQ(&drag_law(law.name), &law);
    EXPECT_EQ(&drag_laws()[drag_law_index(law)], &law);
  }
  // The checkpoint fingerprint codes a law by its row: the first two rows stay put.
  EXPECT_EQ(drag_law_index(drag_law("ergun_wen_yu")), 0u);
  EXPECT_EQ(drag_law_index(drag_law("stokes")), 1u);
  EXPECT_EQ(find_drag_law("ergun"), nullptr);
  EXPECT_THROW(static_cast<void>(drag_law("ergun")), std::invalid_argument);
}

}  // namespace
}  // namespace fdem
