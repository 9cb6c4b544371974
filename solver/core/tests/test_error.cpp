#include "core/error.hpp"

#include <gtest/gtest.h>

TEST(InputError, MessageNamesFileLineKeyAndValue) {
  const fdem::InputError e("scene.yaml", "particles.diameter", "-1e-3", "must be positive", 12);
  EXPECT_STREQ(e.what(), "scene.yaml:12: key 'particles.diameter' = '-1e-3': must be positive");
  EXPECT_EQ(e.line(), 12);
}

TEST(InputError, MessageWithoutLineOmitsIt) {
  const fdem::InputError e("s.yaml", "fluid.viscosity", "0", "must be positive");
  EXPECT_STREQ(e.what(), "s.yaml: key 'fluid.viscosity' = '0': must be positive");
}
