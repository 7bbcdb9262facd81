// Tests of the thin-plate-spline terrain from control points
// (core/terrain_interpolation.hpp; docs/model.md §6).
#include "core/terrain_interpolation.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rover {
namespace {

std::vector<Eigen::Vector3d> random_points(int n, unsigned seed, double (*h)(double, double)) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-2.0, 3.0), y(-1.0, 1.5);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) {
    const double px = x(rng), py = y(rng);
    points.emplace_back(px, py, h(px, py));
  }
  return points;
}

double hills(double x, double y) { return 0.1 * std::sin(2 * x) * std::cos(3 * y) + 0.02 * x; }
double plane(double x, double y) { return 0.3 - 0.12 * x + 0.07 * y; }

TEST(ThinPlateSpline, PassesExactlyThroughTheControlPoints) {
  const auto points = random_points(150, 7, hills);
  const ThinPlateSpline spline(points);
  for (const auto& p : points) EXPECT_NEAR(spline(p.x(), p.y()), p.z(), 1e-10);
}

TEST(ThinPlateSpline, ReproducesAPlaneExactly) {
  const auto points = random_points(40, 11, plane);
  const ThinPlateSpline spline(points);
  // Everywhere, not only at the points (and even outside their hull).
  for (double x = -3.0; x <= 4.0; x += 0.37)
    for (double y = -2.0; y <= 2.5; y += 0.41) EXPECT_NEAR(spline(x, y), plane(x, y), 1e-11);
}

TEST(ThinPlateSpline, IsInvariantUnderTranslationAndScaleOfTheCoordinates) {
  // The same shape in kilometres far from the origin: the spline must agree
  // (the solve centres and scales; a naive one loses accuracy here).
  auto points = random_points(60, 3, hills);
  const ThinPlateSpline reference(points);
  for (auto& p : points) p.head<2>() = p.head<2>() * 1000.0 + Eigen::Vector2d(5e5, -3e5);
  const ThinPlateSpline moved(points);
  for (double x = -1.5; x <= 2.5; x += 0.5)
    for (double y = -0.5; y <= 1.0; y += 0.5)
      EXPECT_NEAR(moved(x * 1000.0 + 5e5, y * 1000.0 - 3e5), reference(x, y), 1e-8);
}

TEST(ThinPlateSpline, ApproximatesASmoothSurfaceBetweenThePoints) {
  // Convergence check: with dense points the spline is close to the surface.
  const auto points = random_points(400, 5, hills);
  const ThinPlateSpline spline(points);
  double worst = 0.0;
  for (double x = -1.5; x <= 2.5; x += 0.13)
    for (double y = -0.7; y <= 1.2; y += 0.11) worst = std::max(worst, std::abs(spline(x, y) - hills(x, y)));
  EXPECT_LT(worst, 5e-3);
}

TEST(GridFromControlPoints, FillsTheGridWithTheSplineAtItsNodes) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0.1}, {1, 0, 0.2}, {0, 1, 0.0}, {1, 1, 0.4}, {0.5, 0.5, 0.3}};
  const GridGeometry geometry{-0.5, -0.25, 0.25, 0.25, 9, 7};
  const HeightGrid grid = grid_from_control_points(points, geometry);
  ASSERT_EQ(grid.nx, 9);
  ASSERT_EQ(grid.ny, 7);
  ASSERT_EQ(grid.heights_m.size(), 63u);
  EXPECT_DOUBLE_EQ(grid.origin_x_m, -0.5);
  EXPECT_DOUBLE_EQ(grid.spacing_y_m, 0.25);
  const ThinPlateSpline spline(points);
  for (int iy = 0; iy < grid.ny; ++iy)
    for (int ix = 0; ix < grid.nx; ++ix)
      EXPECT_DOUBLE_EQ(grid.at(ix, iy), spline(grid.node_x(ix), grid.node_y(iy)));
  // Control points on nodes come out exactly: (0.5, 0.5) is node (4, 3).
  EXPECT_NEAR(grid.at(4, 3), 0.3, 1e-12);
  EXPECT_NEAR(grid.at(6, 5), 0.4, 1e-12);  // (1, 1)
  EXPECT_NO_THROW((void)Terrain::from_grid(grid));
}

TEST(GridFromControlPoints, ThreePointsGiveTheirPlane) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, plane(0, 0)}, {2, 0, plane(2, 0)}, {0, 1, plane(0, 1)}};
  const HeightGrid grid = grid_from_control_points(points, {-1, -1, 0.5, 0.5, 8, 6});
  for (int iy = 0; iy < grid.ny; ++iy)
    for (int ix = 0; ix < grid.nx; ++ix)
      EXPECT_NEAR(grid.at(ix, iy), plane(grid.node_x(ix), grid.node_y(iy)), 1e-13);
}

TEST(GridFromControlPoints, RejectsPointsThatDoNotDefineAUniqueSurface) {
  const auto rejects = [](const std::vector<Eigen::Vector3d>& points, const std::string& words) {
    try {
      (void)grid_from_control_points(points, {0, 0, 0.1, 0.1, 3, 3});
      ADD_FAILURE() << "accepted points that should be rejected for: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  rejects({{0, 0, 0}, {1, 0, 1}}, "at least 3 points, got 2");
  rejects({{0, 0, 0}, {1, 0, 1}, {2, 0, 0}, {3, 0, 5}}, "one line");
  rejects({{0, 0, 0}, {1, 1, 1}, {0, 1, 2}, {1, 1, 3}}, "points 1 (1, 1, 1) and 3 (1, 1, 3) have the same (x, y)");
  rejects({{0, 0, 0}, {1, 0, 0}, {0, 1, std::nan("")}}, "point 2 is not finite");
  rejects({{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}}, "point 2 is not finite");
  rejects({{1, 1, 0}, {1, 1, 1}, {1, 1, 2}}, "same (x, y)");
  EXPECT_THROW((void)grid_from_control_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 0, 0.0, 0.1, 3, 3}),
               std::invalid_argument);
  EXPECT_THROW((void)grid_from_control_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 0, 0.1, 0.1, 1, 3}),
               std::invalid_argument);
}

}  // namespace
}  // namespace rover
