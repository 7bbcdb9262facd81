// `rover terrain`: generates terrain files reproducibly. `rover terrain obstacle`
// writes the trapezoid obstacle of docs/model.md §7 as a height grid
// (core/obstacle.hpp) in the "grid" format of io/terrain_json.hpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>
#include <utility>

#include "core/obstacle.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/held_outputs.hpp"
#include "drivers/interruptible_outputs.hpp"
#include "drivers/options.hpp"
#include "io/plot.hpp"
#include "io/terrain_json.hpp"

namespace rover::cli {
namespace {

struct ObstacleOptions {
  std::string out;
  std::string png;
  double spacing_m = 0.001;
  double margin_m = 0.005;
  TrapezoidObstacle obstacle;
  double ramp_angle_deg = 20.0;
};

// The grid's heights as a PNG; a plot that cannot be drawn is a warning.
void plot_obstacle(const HeightGrid& grid, const std::string& png, InterruptibleOutputs& outputs) {
  io::SurfacePlot plot;
  plot.title = "Trapezoid obstacle (docs/model.md §7): terrain height [m]";
  plot.x_label = "x [m]";
  plot.y_label = "y [m]";
  plot.z_label = "height [m]";
  for (int ix = 0; ix < grid.nx; ++ix) plot.x.push_back(grid.node_x(ix));
  for (int iy = 0; iy < grid.ny; ++iy) plot.y.push_back(grid.node_y(iy));
  plot.z = grid.heights_m;
  plot.contour_levels = 4;
  plot.height_px = 500;
  try {
    io::write_png(plot, png);
    std::cout << "wrote " << png << "\n";
  } catch (const io::PlotError& e) {
    outputs.stop_if_signalled();  // gnuplot ended by the same Ctrl-C: said as the interrupt it is
    std::cerr << "rover terrain: warning: no plot: " << e.what() << "\n";
    return;
  }
  outputs.written(png);
}

// A length flag within the scale every terrain reader accepts (core/model_scale.hpp).
void within_position_scale(FlagChecks& checks, const std::string& flag, double value) {
  if (!std::isfinite(value)) return;  // said by finite()
  if (const std::string p = beyond_scale(value, kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
    checks.add(flag + " " + p + "; the terrain readers refuse such a grid");
}

// The grid must hold the obstacle's shape: every ramp and the top span at
// least one spacing, so that a node lies on each (a coarser grid turns the
// trapezoid into a tent of the wrong height).
void require_resolved(const TrapezoidObstacle& obstacle, const ObstacleOptions& o) {
  const double ramp = obstacle.ramp_length_m();
  const bool top = obstacle.top_length_m > 0.0;
  const double finest = top ? std::min(ramp, obstacle.top_length_m) : ramp;
  if (o.spacing_m <= finest * (1.0 + 1e-9)) return;
  if (finest < kMinTerrainSpacing_m)
    throw CommandLineError({ramp <= finest
        ? "the obstacle's ramps are " + number_text(ramp) + " m long (--height " + number_text(obstacle.height_m) +
              " m at --ramp-angle-deg " + number_text(o.ramp_angle_deg) + "), shorter than the finest grid the "
              "terrain readers accept (" + number_text(kMinTerrainSpacing_m) + " m): give a smaller "
              "--ramp-angle-deg or a greater --height"
        : "the obstacle's top is " + number_text(obstacle.top_length_m) + " m long (--top-length), shorter than "
              "the finest grid the terrain readers accept (" + number_text(kMinTerrainSpacing_m) + " m): give a "
              "longer top, or --top-length 0 for a ridge"});
  throw CommandLineError({"--spacing " + number_text(o.spacing_m) + " m does not resolve the obstacle: its ramps are " +
                          number_text(ramp) + " m long (--height " + number_text(obstacle.height_m) +
                          " m at --ramp-angle-deg " + number_text(o.ramp_angle_deg) + ")" +
                          (top ? " and its top " + number_text(obstacle.top_length_m) + " m (--top-length)" : "") +
                          ", so no grid node would lie on " + (ramp <= finest ? "a ramp" : "the top") +
                          "; give a spacing of at most " + number_text(finest) + " m"});
}

// The far edges of the grid within the scale the readers accept.
void require_readable_extent(const HeightGrid& grid) {
  FlagChecks checks;
  const double x_end = grid.node_x(grid.nx - 1), y_end = grid.node_y(grid.ny - 1);
  for (const auto& [what, value] : {std::pair<const char*, double>{"x", grid.origin_x_m}, {"x", x_end},
                                    {"y", grid.origin_y_m}, {"y", y_end}})
    if (const std::string p = beyond_scale(value, kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
      checks.add(std::string("the grid's ") + what + " edge (--foot-x or --y-min/--y-max with the ramps, " +
                 "--top-length and --margin) at " + p + "; the terrain readers refuse such a grid");
  checks.throw_if_any();
}

int run_obstacle(const ObstacleOptions& o) {
  // Each flag by name (core/obstacle checks the same ranges by field name).
  FlagChecks checks;
  checks.output_file("--out", o.out, /*regular_only=*/true);
  checks.output_format("--out", o.out, "JSON", ".json");
  checks.output_file("--png", o.png, /*regular_only=*/true);
  checks.output_format("--png", o.png, "PNG", ".png");
  checks.distinct_files("--png", o.png, "--out", o.out);
  if (!o.png.empty()) checks.plotter("--png", "give no --png");
  checks.positive("--spacing", o.spacing_m);
  checks.non_negative("--margin", o.margin_m);
  checks.finite("--foot-x", o.obstacle.foot_x_m);
  checks.positive("--height", o.obstacle.height_m);
  if (!(o.ramp_angle_deg > 0.0 && o.ramp_angle_deg < 90.0))
    checks.add("--ramp-angle-deg must lie in (0, 90), got " + number_text(o.ramp_angle_deg));
  checks.non_negative("--top-length", o.obstacle.top_length_m);
  checks.finite("--y-min", o.obstacle.y_min_m);
  checks.finite("--y-max", o.obstacle.y_max_m);
  within_position_scale(checks, "--foot-x", o.obstacle.foot_x_m);
  within_position_scale(checks, "--y-min", o.obstacle.y_min_m);
  within_position_scale(checks, "--y-max", o.obstacle.y_max_m);
  within_position_scale(checks, "--height", o.obstacle.height_m);
  if (o.spacing_m > 0.0 && o.spacing_m < kMinTerrainSpacing_m)
    checks.add("--spacing " + number_text(o.spacing_m) + " m is below " + number_text(kMinTerrainSpacing_m) +
               " m (the wheel radius is centimetres: metres expected); the terrain readers refuse such a grid");
  if (!(o.obstacle.y_min_m < o.obstacle.y_max_m))
    checks.add("--y-min (" + number_text(o.obstacle.y_min_m) + ") must be below --y-max (" +
               number_text(o.obstacle.y_max_m) + ")");
  checks.throw_if_any();
  TrapezoidObstacle obstacle = o.obstacle;
  obstacle.ramp_angle_rad = o.ramp_angle_deg * std::numbers::pi / 180.0;
  require_resolved(obstacle, o);
  InterruptibleOutputs outputs({o.out, o.png});  // a signal stops the work with a word, never halfway through a file
  HeightGrid grid;
  try {
    grid = trapezoid_obstacle_grid(obstacle, o.spacing_m, o.margin_m);
  } catch (const std::invalid_argument& e) {
    throw CommandLineError({"--spacing " + number_text(o.spacing_m) + ", --margin " + number_text(o.margin_m) +
                            ", --height " + number_text(obstacle.height_m) + ", --ramp-angle-deg " +
                            number_text(o.ramp_angle_deg) + ", --top-length " + number_text(obstacle.top_length_m) +
                            ", --y-min " + number_text(obstacle.y_min_m) + ", --y-max " +
                            number_text(obstacle.y_max_m) + ": " + e.what()});
  }

  require_readable_extent(grid);

  std::ostringstream description;
  description << "Trapezoid obstacle of docs/model.md §7 (obstacle negotiation): foot at x = "
              << obstacle.foot_x_m << " m, height " << obstacle.height_m << " m, "
              << o.ramp_angle_deg << " deg ramps, top " << obstacle.top_length_m
              << " m, sides y = " << obstacle.y_min_m << " and " << obstacle.y_max_m
              << " m; grid nodes on the foot and on both sides.";
  const io::Json provenance = {
      {"description", description.str()},
      {"generator",
       {{"command", "rover terrain obstacle"},
        {"version", ROVER_VERSION},
        {"foot_x_m", obstacle.foot_x_m},
        {"height_m", obstacle.height_m},
        {"ramp_angle_deg", o.ramp_angle_deg},
        {"ramp_length_m", obstacle.ramp_length_m()},
        {"top_length_m", obstacle.top_length_m},
        {"y_min_m", obstacle.y_min_m},
        {"y_max_m", obstacle.y_max_m},
        {"spacing_m", o.spacing_m},
        {"margin_m", o.margin_m}}}};
  HeldOutputs held;
  held.hold("--out", o.out);
  held.hold("--png", o.png);
  outputs.stop_if_signalled();
  io::save_terrain_grid(grid, o.out, provenance);
  outputs.written(o.out);

  std::cout << "wrote " << o.out << ": " << grid.nx << " x " << grid.ny << " grid, spacing "
            << grid.spacing_x_m << " x " << grid.spacing_y_m << " m, x in [" << grid.node_x(0)
            << ", " << grid.node_x(grid.nx - 1) << "], y in [" << grid.node_y(0) << ", "
            << grid.node_y(grid.ny - 1) << "], ramp length " << obstacle.ramp_length_m()
            << " m, " << std::filesystem::file_size(o.out) << " bytes\n";
  if (!o.png.empty()) plot_obstacle(grid, o.png, outputs);
  return 0;
}

const RegisterCommand terrain_command{
    30, "terrain", "Generate terrain files (the obstacle of docs/model.md §7)",
    [](CLI::App& app) -> std::function<int()> {
      app.require_subcommand(1);
      app.footer(
          "Terrain files are JSON: {\"type\": \"flat\", \"height\": 0}, {\"type\": \"grid\", "
          "\"origin\", \"spacing\", \"counts\", \"heights\"} or {\"type\": \"control_points\", "
          "...} (docs/configuration.md, \"Terrain files\"). A scenario names one in its \"terrain\" field; "
          "rover eom takes one with --terrain FILE.");

      auto o = std::make_shared<ObstacleOptions>();
      CLI::App* obstacle = app.add_subcommand(
          "obstacle", "Write the trapezoid obstacle (docs/model.md §7) as a height grid");
      obstacle->footer(
          "The obstacle: 0 before the foot, a ramp rising at --ramp-angle-deg to --height, a flat "
          "top of --top-length, a ramp falling back to 0; laterally y in [--y-min, --y-max] with "
          "vertical sides. Grid nodes lie exactly on x = foot and on both sides, so the sharp "
          "edges are rounded over at most one spacing by the bilinear terrain; zero-height nodes "
          "(--margin) surround it so the terrain outside the grid is the ground z = 0. Heights "
          "are rounded to 1e-12 m. The defaults reproduce docs/model.md §7 (ramps 0.2747 m "
          "long).\n\nExample (regenerates the shipped file):\n"
          "  rover terrain obstacle --out configs/terrains/obstacle.json --png obstacle.png\n"
          "  rover eom --terrain configs/terrains/obstacle.json --state state.json");
      obstacle->add_option("--out", o->out, "Terrain file to write (JSON)")->required();
      obstacle->add_option("--png", o->png, "Also plot the height map to this PNG file");
      obstacle->add_option("--spacing", o->spacing_m, "Grid spacing [m]")->capture_default_str();
      obstacle->add_option("--margin", o->margin_m, "Zero-height margin around the obstacle [m]")
          ->capture_default_str();
      obstacle->add_option("--foot-x", o->obstacle.foot_x_m, "x of the foot of the rising ramp [m]")
          ->capture_default_str();
      obstacle->add_option("--height", o->obstacle.height_m, "Obstacle height [m]")->capture_default_str();
      obstacle->add_option("--ramp-angle-deg", o->ramp_angle_deg, "Ramp angle [deg]")->capture_default_str();
      obstacle->add_option("--top-length", o->obstacle.top_length_m, "Length of the flat top [m]")
          ->capture_default_str();
      obstacle->add_option("--y-min", o->obstacle.y_min_m, "Right lateral side [m]")->capture_default_str();
      obstacle->add_option("--y-max", o->obstacle.y_max_m, "Left lateral side [m]")->capture_default_str();
      return [o, obstacle]() -> int {
        if (obstacle->parsed()) return run_obstacle(*o);
        return 1;
      };
    }};

}  // namespace
}  // namespace rover::cli
