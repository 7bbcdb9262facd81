// Tests of the terrain height field (core/terrain.hpp; docs/model.md §6).
#include "core/terrain.hpp"

#include <cmath>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "model_fixtures.hpp"

namespace rover {
namespace {

// A smooth, non-planar surface: bilinear interpolation of it has slope jumps
// on every grid line.
double bumpy(double x, double y) { return 0.05 * std::sin(3.0 * x) * std::cos(2.0 * y) + 0.1 * x * x; }

Terrain bumpy_terrain() {
  return Terrain::from_grid(testing::sampled_grid(-1.0, -0.5, 0.1, 0.05, 21, 21, bumpy));
}

TEST(Terrain, FlatPlaneHasHeightAndVerticalNormalEverywhere) {
  const Terrain t = Terrain::flat(0.25);
  EXPECT_TRUE(t.is_flat());
  EXPECT_EQ(t.grid(), nullptr);
  for (double x : {-1e6, 0.0, 3.7})
    for (double y : {-2.0, 0.0, 1e5}) {
      EXPECT_EQ(t.height(x, y), 0.25);
      EXPECT_EQ(t.gradient(x, y), Eigen::Vector2d::Zero());
      EXPECT_EQ(t.normal(x, y), Eigen::Vector3d::UnitZ());
    }
  EXPECT_EQ(t.flat_height(), 0.25);
  EXPECT_EQ(t.max_height(), 0.25);
  EXPECT_EQ(Terrain().height(1.0, 2.0), 0.0);
  EXPECT_TRUE(Terrain().is_flat());
}

TEST(Terrain, BilinearReproducesATiltedPlaneExactly) {
  const double a = 0.3, b = -0.17, c = 0.02;
  const auto plane = [&](double x, double y) { return c + a * x + b * y; };
  const Terrain t = Terrain::from_grid(testing::sampled_grid(-0.7, 0.2, 0.013, 0.021, 40, 30, plane));
  EXPECT_FALSE(t.is_flat());
  const Eigen::Vector3d expected_normal = Eigen::Vector3d(-a, -b, 1.0).normalized();
  // Interior points, grid lines and nodes alike: the plane has no slope jump.
  for (double x = -0.69; x < -0.7 + 39 * 0.013; x += 0.0371)
    for (double y = 0.21; y < 0.2 + 29 * 0.021; y += 0.0433) {
      EXPECT_NEAR(t.height(x, y), plane(x, y), 1e-14);
      const TerrainSample s = t.sample(x, y);
      EXPECT_NEAR(s.height_m, plane(x, y), 1e-14);
      EXPECT_NEAR(s.gradient.x(), a, 1e-12);
      EXPECT_NEAR(s.gradient.y(), b, 1e-12);
      EXPECT_NEAR((t.normal(x, y) - expected_normal).norm(), 0.0, 1e-12);
    }
  const HeightGrid& g = *t.grid();
  for (int ix : {0, 1, 17, 39})
    for (int iy : {0, 5, 29}) {
      const TerrainSample s = t.sample(g.node_x(ix), g.node_y(iy));
      EXPECT_NEAR(s.height_m, plane(g.node_x(ix), g.node_y(iy)), 1e-14);
      // Interior grid lines: both one-sided slopes are the plane's.
      if (ix > 0 && ix < 39) {
        EXPECT_NEAR(s.gradient.x(), a, 1e-12);
      }
      if (iy > 0 && iy < 29) {
        EXPECT_NEAR(s.gradient.y(), b, 1e-12);
      }
    }
}

TEST(Terrain, GradientEqualsFiniteDifferencesAwayFromGridLines) {
  const Terrain t = bumpy_terrain();
  const double step = 1e-6;
  int checked = 0;
  for (double x = -0.93; x < 0.95; x += 0.117)
    for (double y = -0.47; y < 0.48; y += 0.061) {
      const Eigen::Vector2d g = t.gradient(x, y);
      const double fd_x = (t.height(x + step, y) - t.height(x - step, y)) / (2 * step);
      const double fd_y = (t.height(x, y + step) - t.height(x, y - step)) / (2 * step);
      EXPECT_NEAR(g.x(), fd_x, 1e-8) << "at " << x << ", " << y;
      EXPECT_NEAR(g.y(), fd_y, 1e-8) << "at " << x << ", " << y;
      EXPECT_DOUBLE_EQ(t.sample(x, y).height_m, t.height(x, y));
      ++checked;
    }
  EXPECT_GT(checked, 200);
}

TEST(Terrain, HeightIsContinuousAcrossGridLines) {
  const Terrain t = bumpy_terrain();
  const HeightGrid& g = *t.grid();
  for (int ix = 1; ix < g.nx - 1; ix += 3) {
    const double x = g.node_x(ix), y = 0.0123;
    EXPECT_NEAR(t.height(x - 1e-12, y), t.height(x + 1e-12, y), 1e-12);
    EXPECT_NEAR(t.height(x, y), bumpy(x, g.node_y(10)) +
                                    (y - g.node_y(10)) / g.spacing_y_m *
                                        (bumpy(x, g.node_y(11)) - bumpy(x, g.node_y(10))),
                1e-14);
  }
}

TEST(Terrain, OnAGridLineTheSlopeAcrossIsTheMeanOfTheOneSidedSlopes) {
  const Terrain t = bumpy_terrain();
  const HeightGrid& g = *t.grid();
  const double y = 0.0311;  // inside a row cell
  for (int ix = 1; ix < g.nx - 1; ix += 4) {
    const double x = g.node_x(ix);
    // One-sided slopes from finite differences on either side (bilinear is
    // linear in x within a cell, so these are exact to round-off).
    const double left = (t.height(x, y) - t.height(x - 1e-4, y)) / 1e-4;
    const double right = (t.height(x + 1e-4, y) - t.height(x, y)) / 1e-4;
    ASSERT_GT(std::abs(right - left), 1e-3) << "the test needs a slope jump";
    const double mean = 0.5 * (left + right);
    for (double offset : {0.0, 5e-10, -5e-10, 9e-10, -9e-10}) {
      EXPECT_NEAR(t.gradient(x + offset, y).x(), mean, 1e-9) << "offset " << offset;
    }
    // Beyond the tolerance band the one-sided slopes are back.
    EXPECT_NEAR(t.gradient(x - 2e-9, y).x(), left, 1e-9);
    EXPECT_NEAR(t.gradient(x + 2e-9, y).x(), right, 1e-9);
    // The along-line component is continuous: same as just off the line.
    EXPECT_NEAR(t.gradient(x, y).y(), t.gradient(x + 2e-9, y).y(), 1e-6);
  }
  // The same for a line of constant y.
  const double x = 0.0517;
  for (int iy = 1; iy < g.ny - 1; iy += 4) {
    const double yl = g.node_y(iy);
    const double below = (t.height(x, yl) - t.height(x, yl - 1e-4)) / 1e-4;
    const double above = (t.height(x, yl + 1e-4) - t.height(x, yl)) / 1e-4;
    EXPECT_NEAR(t.gradient(x, yl).y(), 0.5 * (below + above), 1e-9);
    EXPECT_NEAR(t.gradient(x, yl + 8e-10).y(), 0.5 * (below + above), 1e-9);
  }
}

TEST(Terrain, AtAGridNodeBothComponentsAreMeans) {
  // A single peak at node (2, 2): the one-sided slopes are +-1 in each
  // direction, so the mean is 0 and the normal is vertical at the node.
  HeightGrid g = testing::sampled_grid(0.0, 0.0, 0.1, 0.1, 5, 5, [](double, double) { return 0.0; });
  g.heights_m[2 * 5 + 2] = 0.1;
  const Terrain peak = Terrain::from_grid(g);
  for (double dx : {0.0, 7e-10, -7e-10})
    for (double dy : {0.0, 7e-10, -7e-10}) {
      const Eigen::Vector2d grad = peak.gradient(0.2 + dx, 0.2 + dy);
      EXPECT_NEAR(grad.x(), 0.0, 1e-12);
      EXPECT_NEAR(grad.y(), 0.0, 1e-12);
    }
  EXPECT_NEAR(peak.normal(0.2, 0.2).z(), 1.0, 1e-12);
  // Just off the node the one-sided slopes appear (slope -1 beyond the peak).
  EXPECT_NEAR(peak.gradient(0.2 + 1e-6, 0.2).x(), -1.0, 1e-5);
  EXPECT_NEAR(peak.gradient(0.2 - 1e-6, 0.2).x(), 1.0, 1e-5);

  // A general surface: at a node, each component is the mean of the slopes
  // along the grid lines through it.
  const Terrain t = bumpy_terrain();
  const HeightGrid& b = *t.grid();
  for (int ix : {3, 10}) {
    for (int iy : {4, 13}) {
      const double x = b.node_x(ix), y = b.node_y(iy);
      const double mean_x = (b.at(ix + 1, iy) - b.at(ix - 1, iy)) / (2 * b.spacing_x_m);
      const double mean_y = (b.at(ix, iy + 1) - b.at(ix, iy - 1)) / (2 * b.spacing_y_m);
      const Eigen::Vector2d grad = t.gradient(x + 3e-10, y - 3e-10);
      EXPECT_NEAR(grad.x(), mean_x, 1e-12);
      EXPECT_NEAR(grad.y(), mean_y, 1e-12);
    }
  }
}

TEST(Terrain, OutsideTheGridTheEdgeValuesExtendFlat) {
  const Terrain t = bumpy_terrain();
  const HeightGrid& g = *t.grid();
  const double x_max = g.node_x(g.nx - 1), y_max = g.node_y(g.ny - 1);
  const double y = 0.0311, x = 0.0517;
  // Across the clamped direction: same height as at the edge, zero slope.
  EXPECT_DOUBLE_EQ(t.height(-5.0, y), t.height(g.origin_x_m, y));
  EXPECT_DOUBLE_EQ(t.height(x_max + 3.0, y), t.height(x_max, y));
  EXPECT_DOUBLE_EQ(t.height(x, -9.0), t.height(x, g.origin_y_m));
  EXPECT_DOUBLE_EQ(t.height(x, y_max + 1e-3), t.height(x, y_max));
  EXPECT_DOUBLE_EQ(t.height(-5.0, 50.0), g.at(0, g.ny - 1));
  EXPECT_EQ(t.gradient(-5.0, y).x(), 0.0);
  EXPECT_EQ(t.gradient(x_max + 1e-3, y).x(), 0.0);
  EXPECT_EQ(t.gradient(x, y_max + 1e-3).y(), 0.0);
  // Along the edge the slope is the edge's own slope.
  EXPECT_NEAR(t.gradient(-5.0, y).y(), t.gradient(g.origin_x_m + 1e-8, y).y(), 1e-6);
  EXPECT_EQ(t.gradient(-5.0, -5.0), Eigen::Vector2d::Zero());
  // On the boundary line the mean rule sees the flat extension outside.
  const double inside = t.gradient(x_max - 1e-6, y).x();
  EXPECT_NEAR(t.gradient(x_max, y).x(), 0.5 * inside, 1e-5 * std::abs(inside) + 1e-9);
  // Heights outside never exceed the grid's bounds.
  EXPECT_LE(t.height(100.0, -100.0), t.max_height());
  EXPECT_GE(t.height(100.0, -100.0), t.min_height());
}

TEST(Terrain, NanInGivesNanOut) {
  const Terrain t = bumpy_terrain();
  EXPECT_TRUE(std::isnan(t.height(std::nan(""), 0.0)));
  EXPECT_TRUE(std::isnan(t.sample(0.0, std::nan("")).gradient.x()));
  EXPECT_TRUE(std::isfinite(t.height(INFINITY, -INFINITY)));
}

TEST(Terrain, InvalidGridsAreRejectedWithAClearMessage) {
  const auto ok = [] { return testing::sampled_grid(0, 0, 0.1, 0.1, 3, 4, [](double x, double) { return x; }); };
  const auto rejects = [](HeightGrid g, const std::string& words) {
    try {
      (void)Terrain::from_grid(std::move(g));
      ADD_FAILURE() << "accepted a grid that should be rejected for: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW((void)Terrain::from_grid(ok()));
  HeightGrid g = ok();
  g.nx = 1;
  g.heights_m.resize(4);
  rejects(g, "at least 2 x 2");
  g = ok();
  g.spacing_y_m = 0.0;
  rejects(g, "spacing");
  g = ok();
  g.spacing_x_m = -0.1;
  rejects(g, "spacing");
  g = ok();
  g.heights_m.pop_back();
  rejects(g, "12 heights, got 11");
  g = ok();
  g.heights_m[7] = std::nan("");
  rejects(g, "(ix 1, iy 2) is not finite");
  g = ok();
  g.origin_x_m = INFINITY;
  rejects(g, "origin");
  EXPECT_THROW((void)Terrain::flat(std::nan("")), std::invalid_argument);
}

TEST(Terrain, CopiesShareTheGridAndAreSafeAcrossThreads) {
  const Terrain t = bumpy_terrain();
  const Terrain copy = t;  // NOLINT(performance-unnecessary-copy-initialization)
  EXPECT_EQ(copy.grid(), t.grid());
  double sums[2] = {0, 0};
  std::thread a([&] { for (int i = 0; i < 1000; ++i) sums[0] += t.height(0.001 * i - 0.5, 0.1); });
  std::thread b([&] { for (int i = 0; i < 1000; ++i) sums[1] += copy.height(0.001 * i - 0.5, 0.1); });
  a.join();
  b.join();
  EXPECT_EQ(sums[0], sums[1]);
}

}  // namespace
}  // namespace rover
