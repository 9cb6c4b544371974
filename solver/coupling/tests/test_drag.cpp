// Drag closures (Eq. 11-15) against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "coupling/drag.hpp"

namespace fdem {
namespace {

const FluidProperties water{1000.0, 1.0e-3};
// Hand values below are rounded to 6 significant digits: compare at 1e-5 relative.
constexpr double hand_rounding = 1e-5;

TEST(Drag, ReynoldsNumberIsEq15WithPorosity) {
  // Re = eps rho |u-v| d / mu = 0.9 * 1000 * 0.05 * 5e-4 / 1e-3 = 22.5
  EXPECT_NEAR(particle_reynolds(0.9, 0.05, 5e-4, water), 22.5, 22.5 * 1e-14);
}

TEST(Drag, DragCoefficientIsRoweHenwoodEq14) {
  // Re = 22.5: Re^0.687 = exp(0.687 ln 22.5) = exp(2.138985) = 8.490815
  // Cd = 24/22.5 (1 + 0.15 * 8.490815) = 1.0666667 * 2.2736223 = 2.425197
  EXPECT_NEAR(drag_coefficient(22.5), 2.425197, 2.425197 * hand_rounding);
  // Above Re = 1000 the Newton value.
  EXPECT_EQ(drag_coefficient(2000.0), 0.44);
}

TEST(Drag, DragCoefficientNearlyContinuousAtReynolds1000) {
  // Re = 1000: 24/1000 (1 + 0.15 * 1000^0.687) = 0.024 * (1 + 0.15 * 115.0867) = 0.438288,
  // against 0.44 just above: a 0.39 % step, which we keep (it is the paper's Eq. 14).
  EXPECT_NEAR(drag_coefficient(1000.0), 0.438288, 0.438288 * hand_rounding);
  EXPECT_NEAR(drag_coefficient(std::nextafter(1000.0, 2000.0)) / drag_coefficient(1000.0), 1.003906, 1e-6);
}

TEST(Drag, WenYuForceMatchesHandComputation) {
  // eps = 0.9 >= 0.8: Wen & Yu (Eq. 13). d = 0.5 mm, particle falling at 0.05 m/s in still water.
  // Re = 22.5, Cd = 2.425197 (above); eps^-2.65 = 0.9^-2.65 = 1.322079
  // beta = 3/4 Cd eps (1-eps) rho |u-v| / d eps^-2.65
  //      = 0.75 * 2.425197 * 0.9 * 0.1 * 1000 * 0.05 / 5e-4 * 1.322079 = 21642.54 kg/(m^3 s)
  // f = pi/6 d^3 beta/(1-eps) (u - v) = 6.544985e-11 * 216425.4 * 0.05 = 7.082504e-7 N, upward (Eq. 11)
  const DragEvaluation e = evaluate_drag(DragLaw::ergun_wen_yu, 0.9, Vec3::Zero(), Vec3(0, 0, -0.05), 5e-4, water);
  EXPECT_NEAR(e.reynolds, 22.5, 1e-12);
  EXPECT_NEAR(e.drag_coefficient, 2.425197, 2.425197 * hand_rounding);
  EXPECT_NEAR(e.beta, 21642.54, 21642.54 * hand_rounding);
  EXPECT_NEAR(e.force.z(), 7.082504e-7, 7.082504e-7 * hand_rounding);
  EXPECT_EQ(e.force.x(), 0.0);
  EXPECT_EQ(e.force.y(), 0.0);
}

TEST(Drag, ErgunForceMatchesHandComputation) {
  // eps = 0.5 < 0.8: Ergun (Eq. 12, Kuipers/Gidaspow form). d = 0.5 mm, slip 0.05 m/s along +x.
  // beta = 150 (1-eps)^2 mu / (eps d^2) + 1.75 (1-eps) rho |u-v| / d
  //      = 150 * 0.25 * 1e-3 / (0.5 * 2.5e-7) + 1.75 * 0.5 * 1000 * 0.05 / 5e-4
  //      = 300000 + 87500 = 387500 kg/(m^3 s)
  // f = 6.544985e-11 * 387500 / 0.5 * 0.05 = 2.536182e-6 N along +x
  const DragEvaluation e = evaluate_drag(DragLaw::ergun_wen_yu, 0.5, Vec3(0.05, 0, 0), Vec3::Zero(), 5e-4, water);
  EXPECT_NEAR(e.beta, 387500.0, 387500.0 * 1e-12);
  EXPECT_NEAR(e.force.x(), 2.536182e-6, 2.536182e-6 * hand_rounding);
  EXPECT_EQ(e.drag_coefficient, 0.0);  // Ergun uses no Cd
}

TEST(Drag, IsolatedSphereLimitIsStandardDrag) {
  // eps = 1: Eq. 11 with Eq. 13 reduces to 1/2 Cd rho (pi d^2 / 4) |u-v|^2 (the 0/0 of beta/(1-eps) cancelled).
  // Re = 25, Cd = 24/25 (1 + 0.15 * 25^0.687) = 0.96 * (1 + 0.15 * 9.128192) = 2.274460
  // f = 0.5 * 2.274460 * 1000 * 1.963495e-7 * 0.0025 = 5.582364e-7 N
  const DragEvaluation e = evaluate_drag(DragLaw::ergun_wen_yu, 1.0, Vec3::Zero(), Vec3(0, 0, -0.05), 5e-4, water);
  EXPECT_TRUE(std::isfinite(e.force.z()));
  EXPECT_NEAR(e.force.z(), 5.582364e-7, 5.582364e-7 * hand_rounding);
  EXPECT_EQ(e.beta, 0.0);  // beta carries the factor (1 - eps)
}

TEST(Drag, ZeroSlipGivesZeroForceAndFiniteCoefficient) {
  for (double eps : {0.4, 0.8, 1.0}) {
    const DragEvaluation e = evaluate_drag(DragLaw::ergun_wen_yu, eps, Vec3::Zero(), Vec3::Zero(), 5e-4, water);
    EXPECT_TRUE(std::isfinite(e.force_coefficient)) << eps;
    EXPECT_EQ(e.force.norm(), 0.0) << eps;
  }
}

TEST(Drag, JumpAtPorosity08IsDocumentedSize) {
  // Viscous limit: K_Ergun / K_WenYu at eps = 0.8 = (150 * 0.2 / 0.8) / (18 * 0.8^-2.65)
  //   = 37.5 / (18 * 1.806390) = 37.5 / 32.51502 = 1.153313
  EXPECT_NEAR(drag_jump_at_switch(1e-9, 5e-4, water), 1.153313, 1.153313 * 1e-5);
  // Re = 0.8 * 1000 * 0.1 * 5e-4 / 1e-3 = 40: Ergun K = 37.5 mu/d^2 + 1.75 rho w / d = 150000 + 350000 = 500000;
  // Wen & Yu: Cd = 24/40 (1 + 0.15 * 40^0.687) = 0.6 * (1 + 0.15 * 12.60710) = 1.734639,
  //   K = 0.75 * 1.734639 * 0.8 * 1000 * 0.1 / 5e-4 * 1.806390 = 376012.2; ratio 1.329743
  EXPECT_NEAR(drag_jump_at_switch(0.1, 5e-4, water), 1.329744, 1.329744 * hand_rounding);
  // The switch itself: eps = 0.8 is Wen & Yu, just below is Ergun.
  const DragEvaluation at = evaluate_drag(DragLaw::ergun_wen_yu, 0.8, Vec3::Zero(), Vec3(0, 0, -0.1), 5e-4, water);
  EXPECT_GT(at.drag_coefficient, 0.0);
}

TEST(Drag, StokesLawIsThreePiMuDV) {
  // f = 3 pi mu d (u - v) = 3 * pi * 1e-3 * 5e-4 * 0.05 = 2.356194e-7 N, any porosity
  for (double eps : {0.5, 1.0}) {
    const DragEvaluation e = evaluate_drag(DragLaw::stokes, eps, Vec3::Zero(), Vec3(0, 0, -0.05), 5e-4, water);
    EXPECT_NEAR(e.force.z(), 2.356194e-7, 2.356194e-7 * hand_rounding) << eps;
  }
}

TEST(Drag, WenYuApproachesStokesAtLowReynoldsInDiluteLimit) {
  // Re -> 0 and eps = 1: Cd -> 24/Re, so Wen & Yu -> Stokes; Re = 1e-4 leaves 0.15 Re^0.687 = 2.7e-4.
  const double w = 1e-4 * water.viscosity / (water.density * 5e-4);
  const double k_wy = force_coefficient(DragLaw::ergun_wen_yu, 1.0, w, 5e-4, water);
  const double k_st = force_coefficient(DragLaw::stokes, 1.0, w, 5e-4, water);
  EXPECT_NEAR(k_wy / k_st, 1.0 + 0.15 * std::pow(1e-4, 0.687), 1e-12);
}

}  // namespace
}  // namespace fdem
