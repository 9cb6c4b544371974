// The Brent root (brent_root.hpp) on a root known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "reference/brent_root.hpp"

namespace fdem {
namespace {

TEST(BrentRoot, FindsTheRootOfACubicToTheAskedWidthAndRefusesANonBracket) {
  // x^3 = 2 on [0, 2]: the bracket shrinks below 1e-13 relative, so the root is within that of 2^(1/3).
  const double root = brent_root([](double x) { return x * x * x - 2.0; }, 0.0, 2.0, 1e-13);
  EXPECT_NEAR(root, std::cbrt(2.0), 1e-12);
  EXPECT_THROW(brent_root([](double x) { return x * x + 1.0; }, -1.0, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace fdem
