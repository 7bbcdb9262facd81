// Tests of the terrain files (io/terrain_json.hpp; docs/model.md §6).
#include "io/terrain_json.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "core/obstacle.hpp"
#include "io/json_reader.hpp"
#include "test_support.hpp"

namespace rover::io {
namespace {

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// The message of the ConfigError that loading `text` raises ("" if none).
std::string load_error(const std::string& text) {
  const std::string path = write_file(rover::testing::temp_dir(), "terrain.json", text);
  try {
    (void)load_terrain(path);
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << "the error must name the file: " << message;
    return message;
  }
  ADD_FAILURE() << "accepted a bad terrain file:\n" << text;
  return "";
}

HeightGrid random_grid(int nx, int ny) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> h(-0.2, 0.3);
  HeightGrid g;
  g.origin_x_m = -1.0 / 3.0;
  g.origin_y_m = 0.1 + 1e-13;
  g.spacing_x_m = 0.01 * std::sqrt(2.0);
  g.spacing_y_m = 1.0 / 7.0;
  g.nx = nx;
  g.ny = ny;
  for (int k = 0; k < nx * ny; ++k) g.heights_m.push_back(k % 5 == 0 ? 0.0 : h(rng));
  g.heights_m[3] = 1e-300;
  g.heights_m[4] = -123456.789e10;
  return g;
}

TEST(TerrainJson, SaveThenLoadGivesIdenticalHeights) {
  const HeightGrid grid = random_grid(37, 23);
  const std::string path = rover::testing::temp_dir() + "/grid.json";
  save_terrain_grid(grid, path, {{"description", "random test grid"}, {"generator", {{"seed", 42}}}});
  const Terrain t = load_terrain(path);
  ASSERT_NE(t.grid(), nullptr);
  const HeightGrid& back = *t.grid();
  EXPECT_EQ(back.nx, grid.nx);
  EXPECT_EQ(back.ny, grid.ny);
  EXPECT_EQ(back.origin_x_m, grid.origin_x_m);
  EXPECT_EQ(back.origin_y_m, grid.origin_y_m);
  EXPECT_EQ(back.spacing_x_m, grid.spacing_x_m);
  EXPECT_EQ(back.spacing_y_m, grid.spacing_y_m);
  EXPECT_EQ(back.heights_m, grid.heights_m);  // bit for bit
  // The row layout: heights[iy][ix].
  const Json json = read_json_file(path);
  EXPECT_EQ(json["heights"].size(), 23u);
  EXPECT_EQ(json["heights"][5].size(), 37u);
  EXPECT_EQ(json["heights"][5][2].get<double>(), grid.at(2, 5));
  EXPECT_EQ(json["description"], "random test grid");
  EXPECT_EQ(json["generator"]["seed"], 42);
  // No temporary left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    ++files;
  EXPECT_EQ(files, 1);
}

TEST(TerrainJson, TheObstacleRoundTripsAndStaysCompact) {
  const HeightGrid grid = trapezoid_obstacle_grid({});
  const std::string path = rover::testing::temp_dir() + "/obstacle.json";
  save_terrain_grid(grid, path);
  EXPECT_EQ(load_terrain(path).grid()->heights_m, grid.heights_m);
  EXPECT_LT(std::filesystem::file_size(path), 2'000'000u);
}

TEST(TerrainJson, LoadsFlatTerrain) {
  const std::string dir = rover::testing::temp_dir();
  const Terrain t = load_terrain(write_file(dir, "flat.json", R"({"type": "flat", "height": -0.5})"));
  EXPECT_TRUE(t.is_flat());
  EXPECT_EQ(t.height(3.0, 4.0), -0.5);
  EXPECT_EQ(load_terrain(write_file(dir, "zero.json", R"({"type": "flat"})")).flat_height(), 0.0);
  // The shipped default.
  const Terrain shipped = load_terrain(rover::testing::source_path("configs/terrains/flat.json"));
  EXPECT_TRUE(shipped.is_flat());
  EXPECT_EQ(shipped.flat_height(), 0.0);
}

TEST(TerrainJson, LoadsAGridWithRowsOfConstantY) {
  const std::string path = write_file(rover::testing::temp_dir(), "g.json", R"({
    "type": "grid", "description": "a ramp along y",
    "origin": [1.0, 2.0], "spacing": [0.5, 0.25], "counts": [3, 2],
    "heights": [[0, 0, 0], [0.1, 0.1, 0.1]]})");
  const Terrain t = load_terrain(path);
  EXPECT_NEAR(t.height(1.7, 2.125), 0.05, 1e-15);
  EXPECT_NEAR(t.gradient(1.7, 2.125).y(), 0.4, 1e-14);
  EXPECT_EQ(t.gradient(1.7, 2.125).x(), 0.0);
}

TEST(TerrainJson, LoadsControlPointsThroughTheThinPlateSpline) {
  // Points on a plane: the grid holds the plane exactly.
  const std::string path = write_file(rover::testing::temp_dir(), "cp.json", R"({
    "type": "control_points", "method": "thin_plate_spline",
    "points": [[0, 0, 0.0], [1, 0, 0.1], [0, 1, 0.2], [1, 1, 0.3], [0.3, 0.6, 0.15]],
    "grid": {"origin": [-0.5, -0.5], "spacing": [0.1, 0.1], "counts": [21, 21]}})");
  const Terrain t = load_terrain(path);
  for (double x : {-0.4, 0.05, 0.77})
    for (double y : {-0.3, 0.5, 1.2}) EXPECT_NEAR(t.height(x, y), 0.1 * x + 0.2 * y, 1e-12);
}

TEST(TerrainJson, BadGridFilesNameTheFileAndTheProblem) {
  const std::string head = R"({"type": "grid", "origin": [0, 0], "spacing": [0.1, 0.1], )";
  EXPECT_NE(load_error(head + R"("counts": [3, 2], "heights": [[0, 0, 0], [0, 0]]})")
                .find("row 1 has 2 values, expected 3"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [3, 3], "heights": [[0, 0, 0], [0, 0, 0]]})")
                .find("has 2 rows, expected ny = 3"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [2, 2], "heights": [[0, null], [0, 0]]})")
                .find("row 0, value 1 is null, expected a finite number"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [2, 2], "heights": [[0, 0], [0, "high"]]})")
                .find("row 1, value 1 is \"high\""),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [2, 2], "heights": [[0, 0], [0, NaN]]})").find("invalid JSON"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [1, 2], "heights": [[0], [0]]})").find("at least 2 x 2"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [2.5, 2], "heights": [[0, 0], [0, 0]]})").find("counts"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "grid", "origin": [0, 0], "spacing": [0.1, 0], "counts": [2, 2],
                           "heights": [[0, 0], [0, 0]]})")
                .find("'spacing'"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "grid", "origin": [0, 0], "spacing": [-0.1, 0.1], "counts": [2, 2],
                           "heights": [[0, 0], [0, 0]]})")
                .find("positive"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "grid", "origin": [0], "spacing": [0.1, 0.1], "counts": [2, 2],
                           "heights": [[0, 0], [0, 0]]})")
                .find("'origin'"),
            std::string::npos);
  EXPECT_NE(load_error(head + R"("counts": [2, 2]})").find("'heights'"), std::string::npos);
}

TEST(TerrainJson, BadTypesAndKeysAreRejected) {
  EXPECT_NE(load_error(R"({"type": "flat", "height": 0.0, "hieght": 1.0})").find("'hieght': unknown key"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "mountain"})").find("unknown terrain type"), std::string::npos);
  EXPECT_NE(load_error(R"({"height": 0.0})").find("'type'"), std::string::npos);
  EXPECT_NE(load_error(R"({"type": "flat", "height": "zero"})").find("'height'"), std::string::npos);
  EXPECT_NE(load_error(R"({"type": "grid", "origin": [0, 0], "spacing": [0.1, 0.1], "counts": [2, 2],
                           "heights": [[0, 0], [0, 0]], "spacing_m": 1})")
                .find("'spacing_m': unknown key"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                           "grid": {"origin": [0, 0], "spacing": [0.1, 0.1], "counts": [2, 2], "extra": 1}})")
                .find("'grid.extra': unknown key"),
            std::string::npos);
}

TEST(TerrainJson, BadControlPointFilesNameTheFileAndTheProblem) {
  const std::string grid = R"("grid": {"origin": [0, 0], "spacing": [0.1, 0.1], "counts": [3, 3]})";
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 0, 0]], )" + grid + "}")
                .find("need at least 3"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 0], [0, 1, 0]], )" + grid + "}")
                .find("point 1 is [1,0], expected [x, y, z]"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 1, 0], [2, 2, 1]], )" + grid + "}")
                .find("one line"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                           "method": "kriging", )" + grid + "}")
                .find("'method'"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"type": "control_points", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                           "grid": {"origin": [0, 0], "spacing": [0.1, 0.1]}})")
                .find("'grid.counts'"),
            std::string::npos);
}

TEST(TerrainJson, MissingFileAndBadSavesFailCleanly) {
  EXPECT_THROW((void)load_terrain("/nonexistent/terrain.json"), ConfigError);
  const std::string dir = rover::testing::temp_dir();
  HeightGrid bad = random_grid(3, 3);
  bad.heights_m.pop_back();
  EXPECT_THROW(save_terrain_grid(bad, dir + "/bad.json"), std::invalid_argument);
  EXPECT_THROW(save_terrain_grid(random_grid(3, 3), dir + "/p.json", {{"author", "me"}}),
               std::invalid_argument);
  EXPECT_THROW(save_terrain_grid(random_grid(3, 3), dir + "/no/such/dir/x.json"), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

// The digest names the ground, not the file: layout, description and a
// constant grid against its plane do not change it; one node's height does.
TEST(TerrainJson, TheDigestChangesWithTheGroundOnly) {
  const std::string dir = rover::testing::temp_dir();
  const std::string ramp = R"("origin": [1.0, 2.0], "spacing": [0.5, 0.25], "counts": [3, 2])";
  const std::string digest = terrain_digest(load_terrain(write_file(
      dir, "a.json", R"({"type": "grid", )" + ramp + R"(, "heights": [[0, 0, 0], [0.1, 0.1, 0.1]]})")));
  EXPECT_EQ(terrain_digest(load_terrain(write_file(dir, "b.json",
                                                   "{\n \"description\": \"the same ramp\",\n \"type\": \"grid\", " +
                                                       ramp + ",\n \"heights\": [[0.0, -0.0, 0e3], [1e-1, 0.1, 0.10]]}"))),
            digest);
  EXPECT_NE(terrain_digest(load_terrain(write_file(
                dir, "c.json", R"({"type": "grid", )" + ramp + R"(, "heights": [[0, 0, 0], [0.1, 0.1, 0.1000001]]})"))),
            digest);
  EXPECT_NE(terrain_digest(load_terrain(write_file(
                dir, "d.json", R"({"type": "grid", "origin": [1.0, 2.0], "spacing": [0.5, 0.5], "counts": [3, 2],
                                  "heights": [[0, 0, 0], [0.1, 0.1, 0.1]]})"))),
            digest);
  const std::string level = R"({"type": "grid", )" + ramp + R"(, "heights": [[0.2, 0.2, 0.2], [0.2, 0.2, 0.2]]})";
  EXPECT_EQ(terrain_digest(load_terrain(write_file(dir, "e.json", level))), terrain_digest(Terrain::flat(0.2)));
  EXPECT_NE(terrain_digest(Terrain::flat(0.2)), terrain_digest(Terrain::flat(0.2000000001)));
  EXPECT_EQ(terrain_digest(Terrain::flat(-0.0)), terrain_digest(Terrain::flat(0.0)));
}

}  // namespace
}  // namespace rover::io
