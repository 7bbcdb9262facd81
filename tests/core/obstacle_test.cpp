// Tests of the trapezoid obstacle grid (core/obstacle.hpp; docs/model.md §7).
#include "core/obstacle.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rover {
namespace {

class ObstacleGrid : public ::testing::Test {
 protected:
  TrapezoidObstacle obstacle;  // docs/model.md §7 defaults
  HeightGrid grid = trapezoid_obstacle_grid(obstacle);
  Terrain terrain = Terrain::from_grid(grid);
  double y_mid = -0.2215;  // the right wheel track
};

TEST_F(ObstacleGrid, HasTheDimensionsOfModelSection7) {
  EXPECT_NEAR(obstacle.ramp_length_m(), 0.10 / std::tan(20.0 * std::numbers::pi / 180.0), 1e-15);
  EXPECT_NEAR(obstacle.ramp_length_m(), 0.2747, 5e-5);
  EXPECT_NEAR(obstacle.far_foot_x_m(), 1.36 + 2 * 0.2747 + 0.30, 1e-4);
  EXPECT_DOUBLE_EQ(grid.spacing_x_m, 0.001);
  EXPECT_NEAR(grid.spacing_y_m, 0.001, 1e-15);
}

TEST_F(ObstacleGrid, IsZeroBeforeTheFootAndBeyondTheFarFoot) {
  for (double x : {-10.0, 0.0, 1.0, 1.3, 1.359, 1.36})
    EXPECT_EQ(terrain.height(x, y_mid), 0.0) << "x = " << x;
  for (double x : {obstacle.far_foot_x_m() + 0.001, 2.5, 100.0})
    EXPECT_EQ(terrain.height(x, y_mid), 0.0) << "x = " << x;
  EXPECT_EQ(terrain.gradient(1.2, y_mid), Eigen::Vector2d::Zero());
  EXPECT_EQ(terrain.min_height(), 0.0);
}

TEST_F(ObstacleGrid, IsTenCentimetresHighOnTheWholeTop) {
  const double top_start = obstacle.foot_x_m + obstacle.ramp_length_m();
  for (double x = top_start + 0.001; x <= top_start + obstacle.top_length_m - 0.001; x += 0.0173)
    for (double y : {obstacle.y_min_m, -0.3, y_mid, -0.15, obstacle.y_max_m}) {
      EXPECT_NEAR(terrain.height(x, y), 0.10, 1e-15) << x << ", " << y;
      // Level between the sides; on a side line the mean rule tilts the normal.
      if (y > obstacle.y_min_m && y < obstacle.y_max_m) {
        EXPECT_NEAR(terrain.normal(x, y).z(), 1.0, 1e-12);
      }
    }
  EXPECT_DOUBLE_EQ(terrain.max_height(), 0.10);
}

TEST_F(ObstacleGrid, RampsRiseAndFallAtTwentyDegrees) {
  const double slope = std::tan(20.0 * std::numbers::pi / 180.0);
  const double L = obstacle.ramp_length_m();
  for (double s = 0.0103; s < L - 0.002; s += 0.0311) {
    const double up = obstacle.foot_x_m + s, down = obstacle.far_foot_x_m() - s;
    EXPECT_NEAR(terrain.height(up, y_mid), s * slope, 2e-12);
    EXPECT_NEAR(terrain.height(down, y_mid), s * slope, 2e-12);
    EXPECT_NEAR(terrain.gradient(up, y_mid).x(), slope, 1e-8);
    EXPECT_NEAR(terrain.gradient(down, y_mid).x(), -slope, 1e-8);
    EXPECT_EQ(terrain.gradient(up, y_mid).y(), 0.0);
    // Agrees with the exact profile.
    EXPECT_NEAR(terrain.height(up, y_mid), obstacle.height_at(up, y_mid), 2e-12);
  }
}

TEST_F(ObstacleGrid, HasNodesExactlyOnTheFootAndBothSides) {
  const auto nearest_node_offset = [](double coord, double origin, double spacing) {
    const double k = std::round((coord - origin) / spacing);
    return std::abs(origin + k * spacing - coord);
  };
  EXPECT_LT(nearest_node_offset(obstacle.foot_x_m, grid.origin_x_m, grid.spacing_x_m), 1e-12);
  EXPECT_LT(nearest_node_offset(obstacle.y_min_m, grid.origin_y_m, grid.spacing_y_m), 1e-12);
  EXPECT_LT(nearest_node_offset(obstacle.y_max_m, grid.origin_y_m, grid.spacing_y_m), 1e-12);
  // The lateral side nodes carry the obstacle (closed interval), the next ones out do not.
  const double x_top = obstacle.foot_x_m + obstacle.ramp_length_m() + 0.1;
  // (Heights at nodes are exact up to the round-off of locating the node.)
  EXPECT_NEAR(terrain.height(x_top, obstacle.y_min_m), 0.10, 1e-14);
  EXPECT_NEAR(terrain.height(x_top, obstacle.y_max_m), 0.10, 1e-14);
  EXPECT_NEAR(terrain.height(x_top, obstacle.y_min_m - grid.spacing_y_m), 0.0, 1e-14);
  EXPECT_NEAR(terrain.height(x_top, obstacle.y_max_m + grid.spacing_y_m), 0.0, 1e-14);
  // On a side line the slope across it is the mean of 0 (on top) and the drop.
  EXPECT_NEAR(terrain.gradient(x_top, obstacle.y_min_m).y(), 0.5 * 0.10 / grid.spacing_y_m, 1e-6);
  EXPECT_NEAR(terrain.gradient(x_top, obstacle.y_max_m).y(), -0.5 * 0.10 / grid.spacing_y_m, 1e-6);
  // The foot is a node: the slope kink sits on it, and the mean rule applies.
  const double slope = std::tan(obstacle.ramp_angle_rad);
  EXPECT_NEAR(terrain.gradient(obstacle.foot_x_m, y_mid).x(), 0.5 * slope, 1e-9);
}

TEST_F(ObstacleGrid, SharpEdgesAreRoundedOverAtMostOneSpacing) {
  const double h = grid.spacing_x_m;
  const double x_top = obstacle.foot_x_m + obstacle.ramp_length_m() + 0.1;
  // Vertical sides: full height on the side line, ground one spacing outside.
  for (double d = 0.0; d <= h; d += h / 8) {
    const double expected = 0.10 * (1.0 - d / grid.spacing_y_m);
    EXPECT_NEAR(terrain.height(x_top, obstacle.y_min_m - d), expected, 1e-12);
    EXPECT_NEAR(terrain.height(x_top, obstacle.y_max_m + d), expected, 1e-12);
  }
  // Every grid height is within one spacing's worth of the exact profile
  // wherever the exact profile is smooth over the whole cell.
  for (double x = 1.2; x < 2.4; x += 0.00077)
    for (double y : {-0.33, obstacle.y_min_m - 0.0005, -0.25, obstacle.y_max_m + 0.0004, -0.1}) {
      // Largest deviation of the interpolant from the profile near an edge:
      // the profile changes by at most 0.1 m over one spacing laterally and
      // by tan(20 deg) * spacing along x.
      double lo = 1e9, hi = -1e9;
      for (double dx : {-h, 0.0, h})
        for (double dy : {-h, 0.0, h}) {
          lo = std::min(lo, obstacle.height_at(x + dx, y + dy));
          hi = std::max(hi, obstacle.height_at(x + dx, y + dy));
        }
      const double z = terrain.height(x, y);
      ASSERT_GE(z, lo - 1e-12) << x << ", " << y;
      ASSERT_LE(z, hi + 1e-12) << x << ", " << y;
    }
}

TEST_F(ObstacleGrid, IsSmallWithAZeroMarginAllAround) {
  EXPECT_LT(grid.nx * grid.ny, 250000);
  for (int ix = 0; ix < grid.nx; ++ix) {
    EXPECT_EQ(grid.at(ix, 0), 0.0);
    EXPECT_EQ(grid.at(ix, grid.ny - 1), 0.0);
  }
  for (int iy = 0; iy < grid.ny; ++iy) {
    EXPECT_EQ(grid.at(0, iy), 0.0);
    EXPECT_EQ(grid.at(grid.nx - 1, iy), 0.0);
  }
  EXPECT_LE(grid.origin_x_m, obstacle.foot_x_m - 0.005 + 1e-12);
  EXPECT_GE(grid.node_x(grid.nx - 1), obstacle.far_foot_x_m() + 0.005 - 1e-12);
}

TEST(TrapezoidObstacle, LateralSidesGetNodesEvenWhenTheWidthIsNotAMultipleOfTheSpacing) {
  TrapezoidObstacle o;
  o.y_min_m = -0.3;
  o.y_max_m = -0.0987;  // 0.2013 m wide
  const HeightGrid g = trapezoid_obstacle_grid(o, 0.002, 0.01);
  const double k_max = (o.y_max_m - g.origin_y_m) / g.spacing_y_m;
  EXPECT_NEAR(k_max, std::round(k_max), 1e-9);
  EXPECT_NEAR(g.spacing_y_m, 0.002, 0.002 * 0.01);
  const Terrain t = Terrain::from_grid(g);
  EXPECT_NEAR(t.height(1.36 + 0.5, o.y_max_m), 0.10, 1e-14);
  EXPECT_NEAR(t.height(1.36 + 0.5, o.y_max_m + g.spacing_y_m), 0.0, 1e-14);
}

TEST(TrapezoidObstacle, RejectsMeaninglessParameters) {
  TrapezoidObstacle o;
  o.ramp_angle_rad = 0.0;
  EXPECT_THROW((void)trapezoid_obstacle_grid(o), std::invalid_argument);
  o = {};
  o.height_m = -0.1;
  EXPECT_THROW((void)trapezoid_obstacle_grid(o), std::invalid_argument);
  o = {};
  o.y_max_m = o.y_min_m;
  EXPECT_THROW((void)trapezoid_obstacle_grid(o), std::invalid_argument);
  EXPECT_THROW((void)trapezoid_obstacle_grid({}, 0.0), std::invalid_argument);
  EXPECT_THROW((void)trapezoid_obstacle_grid({}, 1e-7), std::invalid_argument);  // far too many nodes
}

}  // namespace
}  // namespace rover
