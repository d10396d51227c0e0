// SPDX-License-Identifier: MIT
/// @file The qualified reference: the reversal map between and beyond its nodes, the residual a
/// qualification leaves, and a bad map as a clear error.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/planning/qualified_reference.hpp>
#include <limits>

namespace {

using cmmcomp::ConfigError;
using cmmcomp::planning::QualifiedReference;

QualifiedReference three_nodes() {
  QualifiedReference q;
  q.sphere_y_mm = 250;
  q.map_y_mm = {0, 250, 500};
  q.map_um = {-4, -5, -8};
  return q;
}

TEST(QualifiedReference, MapIsLinearBetweenNodesAndFlatBeyond) {
  const QualifiedReference q = three_nodes();
  EXPECT_DOUBLE_EQ(q.map_at_um(0), -4);
  EXPECT_DOUBLE_EQ(q.map_at_um(125), -4.5);
  EXPECT_DOUBLE_EQ(q.map_at_um(250), -5);
  EXPECT_DOUBLE_EQ(q.map_at_um(400), -5 + 0.6 * -3);
  EXPECT_DOUBLE_EQ(q.map_at_um(500), -8);
  EXPECT_DOUBLE_EQ(q.map_at_um(-10), -4);
  EXPECT_DOUBLE_EQ(q.map_at_um(900), -8);
  EXPECT_DOUBLE_EQ(q.map_at_um(std::numeric_limits<double>::quiet_NaN()), -4);
  QualifiedReference one;
  one.map_y_mm = {100};
  one.map_um = {-3};
  EXPECT_DOUBLE_EQ(one.map_at_um(0), -3);
  EXPECT_DOUBLE_EQ(one.map_at_um(900), -3);
  EXPECT_DOUBLE_EQ(QualifiedReference{}.map_at_um(1), 0);
}

TEST(QualifiedReference, LeavesHowTheDynamicLagChangesFromTheSphere) {
  const QualifiedReference q = three_nodes();
  // At the sphere nothing remains, whatever the lag.
  EXPECT_DOUBLE_EQ(q.residual_um(-7.3, 250, -7.3), 0);
  // A lag that is the map's plus a constant is removed everywhere.
  EXPECT_NEAR(q.residual_um(-8 - 1.2, 500, -5 - 1.2), 0, 1e-12);
  // A dynamic part that grows from 1.0 µm at the sphere to 1.6 µm at Y 500 leaves 0.6 µm.
  EXPECT_NEAR(q.residual_um(-8 - 1.6, 500, -5 - 1.0), -0.6, 1e-12);
}

TEST(QualifiedReference, ABadMapIsAClearError) {
  EXPECT_NO_THROW(three_nodes().validate());
  QualifiedReference q = three_nodes();
  q.map_um.pop_back();
  EXPECT_THROW(q.validate(), ConfigError);
  q = three_nodes();
  q.map_y_mm = {0, 500, 250};
  EXPECT_THROW(q.validate(), ConfigError);
  q = three_nodes();
  q.map_y_mm = {0, 250, 250};
  EXPECT_THROW(q.validate(), ConfigError);
  q = three_nodes();
  q.map_um[1] = std::nan("");
  EXPECT_THROW(q.validate(), ConfigError);
  q = three_nodes();
  q.sphere_y_mm = std::numeric_limits<double>::infinity();
  EXPECT_THROW(q.validate(), ConfigError);
  EXPECT_THROW(QualifiedReference{}.validate(), ConfigError);
}

}  // namespace
