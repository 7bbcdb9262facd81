// PNG plots through gnuplot (io/plot.hpp): files are real PNGs of the asked
// size, written atomically; bad input and bad destinations throw.
#include "io/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

struct PngHeader {
  bool signature_ok = false;
  unsigned width = 0, height = 0;
};

// The 8-byte signature and the IHDR size (big-endian at bytes 16..23).
PngHeader read_png_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 24> b{};
  in.read(reinterpret_cast<char*>(b.data()), b.size());
  PngHeader h;
  if (!in) return h;
  const std::array<unsigned char, 8> signature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  h.signature_ok = std::equal(signature.begin(), signature.end(), b.begin());
  const auto be32 = [&](int at) {
    return (unsigned(b[at]) << 24) | (unsigned(b[at + 1]) << 16) | (unsigned(b[at + 2]) << 8) |
           unsigned(b[at + 3]);
  };
  h.width = be32(16);
  h.height = be32(20);
  return h;
}

int files_in(const std::string& dir) {
  int n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

LinePlot sine_plot() {
  LinePlot plot;
  plot.title = "it's a `test` with $x, @y and v_s^2";  // quotes and markup print literally
  plot.x_label = "t [s]";
  plot.y_label = "z [m]";
  Series sine{.label = "sin"};
  Series cosine{.label = "cos", .style = SeriesStyle::dashed, .color = "black"};
  Band band{.label = "+-0.2", .color = "#1f77b4"};
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.1 * i;
    sine.x.push_back(t);
    sine.y.push_back(std::sin(t));
    cosine.x.push_back(t);
    cosine.y.push_back(i == 50 ? std::nan("") : std::cos(t));  // a gap
    band.x.push_back(t);
    band.lower.push_back(std::sin(t) - 0.2);
    band.upper.push_back(std::sin(t) + 0.2);
  }
  plot.series = {sine, cosine};
  plot.bands = {band};
  plot.width_px = 640;
  plot.height_px = 480;
  return plot;
}

TEST(Plot, LinePlotIsAPngOfTheRequestedSize) {
  const std::string dir = testing::temp_dir();
  const std::string path = dir + "/line.png";
  write_png(sine_plot(), path);
  const PngHeader h = read_png_header(path);
  EXPECT_TRUE(h.signature_ok);
  EXPECT_EQ(h.width, 640u);
  EXPECT_EQ(h.height, 480u);
  EXPECT_EQ(files_in(dir), 1);  // no temp files left behind
  write_png(sine_plot(), path);  // replaces an existing file
  EXPECT_EQ(files_in(dir), 1);
  fs::remove_all(dir);
}

TEST(Plot, SurfacePlotIsAPng) {
  SurfacePlot plot{.title = "Rosenbrock", .x_label = "x", .y_label = "y", .z_label = "log10 f"};
  for (int i = 0; i < 30; ++i) plot.x.push_back(-2.0 + 4.0 * i / 29);
  for (int j = 0; j < 20; ++j) plot.y.push_back(-1.0 + 4.0 * j / 19);
  for (double y : plot.y)
    for (double x : plot.x)
      plot.z.push_back(std::log10(1.0 + std::pow(1 - x, 2) + 100 * std::pow(y - x * x, 2)));
  plot.overlays = {Series{
      .label = "minimum", .x = {1.0}, .y = {1.0}, .style = SeriesStyle::points, .color = "red"}};
  const std::string dir = testing::temp_dir();
  const std::string path = dir + "/surface.png";
  write_png(plot, path);
  const PngHeader h = read_png_header(path);
  EXPECT_TRUE(h.signature_ok);
  EXPECT_EQ(h.width, 1000u);
  EXPECT_EQ(files_in(dir), 1);
  fs::remove_all(dir);
}

TEST(Plot, MissingDirectoryThrowsAndWritesNothing) {
  const std::string dir = testing::temp_dir();
  const std::string path = dir + "/no/such/dir/line.png";
  EXPECT_THROW(write_png(sine_plot(), path), PlotError);
  EXPECT_FALSE(fs::exists(dir + "/no"));
  fs::remove_all(dir);
}

TEST(Plot, InconsistentDataThrows) {
  const std::string dir = testing::temp_dir();
  LinePlot ragged = sine_plot();
  ragged.series[0].y.pop_back();
  EXPECT_THROW(write_png(ragged, dir + "/a.png"), std::invalid_argument);
  LinePlot bad_colour = sine_plot();
  bad_colour.series[0].color = "red' ; system 'ls";
  EXPECT_THROW(write_png(bad_colour, dir + "/b.png"), std::invalid_argument);
  EXPECT_THROW(write_png(LinePlot{}, dir + "/c.png"), std::invalid_argument);
  SurfacePlot surface;
  surface.x = {0, 1, 2};
  surface.y = {0, 1};
  surface.z = {0, 1, 2, 3, 4};  // needs 6
  EXPECT_THROW(write_png(surface, dir + "/d.png"), std::invalid_argument);
  EXPECT_EQ(files_in(dir), 0);
  fs::remove_all(dir);
}

// A 2x2 grid: the sine plot, a blank cell, a scatter and a log-log line.
PanelGrid two_by_two() {
  LinePlot scatter{.title = "scatter", .x_label = "a [m]", .y_label = "b [s]"};
  Series points{.style = SeriesStyle::points, .color = "#80204080"};
  for (int i = 0; i < 200; ++i) {
    points.x.push_back(std::cos(0.1 * i));
    points.y.push_back(std::sin(0.3 * i));
  }
  scatter.series = {points};
  LinePlot power{.title = "y = x^2", .x_label = "x", .y_label = "y", .log_x = true, .log_y = true};
  Series square{.label = "x^2"};
  for (int i = 1; i <= 50; ++i) {
    square.x.push_back(0.1 * i);
    square.y.push_back(0.01 * i * i);
  }
  power.series = {square};
  return PanelGrid{.title = "grid 'of' panels",
                   .rows = 2,
                   .cols = 2,
                   .panels = {sine_plot(), std::nullopt, scatter, power},
                   .width_px = 900,
                   .height_px = 700};
}

std::string refusal(const PanelGrid& grid, const std::string& path) {
  try {
    write_png(grid, path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(not refused)";
}

TEST(Plot, PanelGridIsOnePngOfTheCanvasSize) {
  const std::string dir = testing::temp_dir();
  const std::string path = dir + "/grid.png";
  write_png(two_by_two(), path);
  const PngHeader h = read_png_header(path);
  EXPECT_TRUE(h.signature_ok);
  EXPECT_EQ(h.width, 900u);  // the grid's canvas, not a panel's (sine_plot is 640x480)
  EXPECT_EQ(h.height, 700u);
  EXPECT_EQ(files_in(dir), 1);
  fs::remove_all(dir);
}

TEST(Plot, InconsistentPanelGridIsRefusedNamingTheProblem) {
  const std::string dir = testing::temp_dir();
  const std::string path = dir + "/grid.png";
  PanelGrid short_of_one = two_by_two();
  short_of_one.panels.pop_back();
  EXPECT_NE(refusal(short_of_one, path).find("needs 4 panels"), std::string::npos) << refusal(short_of_one, path);
  EXPECT_NE(refusal(short_of_one, path).find("got 3"), std::string::npos);
  PanelGrid no_rows = two_by_two();
  no_rows.rows = 0;
  EXPECT_NE(refusal(no_rows, path).find("at least one row"), std::string::npos) << refusal(no_rows, path);
  const PanelGrid blank{.rows = 1, .cols = 2, .panels = {std::nullopt, std::nullopt}};
  EXPECT_NE(refusal(blank, path).find("only blank cells"), std::string::npos) << refusal(blank, path);
  PanelGrid ragged = two_by_two();
  ragged.panels[2]->series[0].y.pop_back();
  const std::string ragged_why = refusal(ragged, path);
  EXPECT_NE(ragged_why.find("panel (row 2, column 1)"), std::string::npos) << ragged_why;
  EXPECT_NE(ragged_why.find("199 values, expected 200"), std::string::npos) << ragged_why;
  PanelGrid opaque = two_by_two();
  opaque.panels[0]->bands[0].opacity = 1.5;
  EXPECT_NE(refusal(opaque, path).find("panel (row 1, column 1)"), std::string::npos) << refusal(opaque, path);
  EXPECT_NE(refusal(opaque, path).find("opacity"), std::string::npos);
  PanelGrid bad_colour = two_by_two();
  bad_colour.panels[3]->series[0].color = "red'; system 'ls";
  EXPECT_NE(refusal(bad_colour, path).find("colour"), std::string::npos) << refusal(bad_colour, path);
  PanelGrid empty_panel = two_by_two();
  empty_panel.panels[3] = LinePlot{};
  EXPECT_NE(refusal(empty_panel, path).find("panel (row 2, column 2): nothing to plot"), std::string::npos)
      << refusal(empty_panel, path);
  PanelGrid tiny = two_by_two();
  tiny.width_px = 50;
  EXPECT_NE(refusal(tiny, path).find("canvas"), std::string::npos) << refusal(tiny, path);
  EXPECT_EQ(files_in(dir), 0);
  fs::remove_all(dir);
}

TEST(Plot, FailingPanelGridLeavesNoFile) {
  // The last panel's only series has no finite point: its sizes are
  // consistent, but gnuplot stops there ("x range is invalid") after drawing
  // the first panels into the temp file.
  PanelGrid grid = two_by_two();
  grid.panels[3]->series[0].y.assign(grid.panels[3]->series[0].x.size(), std::nan(""));
  const std::string dir = testing::temp_dir();
  EXPECT_THROW(write_png(grid, dir + "/grid.png"), PlotError);
  EXPECT_EQ(files_in(dir), 0);  // neither the PNG nor the partial file
  // An existing plot survives a failing rewrite untouched.
  write_png(two_by_two(), dir + "/grid.png");
  const auto size = fs::file_size(dir + "/grid.png");
  EXPECT_THROW(write_png(grid, dir + "/grid.png"), PlotError);
  EXPECT_EQ(files_in(dir), 1);
  EXPECT_EQ(fs::file_size(dir + "/grid.png"), size);
  EXPECT_EQ(read_png_header(dir + "/grid.png").width, 900u);
  fs::remove_all(dir);
}

TEST(Plot, PanelGridOrWarnLogsInsteadOfThrowing) {
  const std::string dir = testing::temp_dir();
  std::ostringstream log;
  PanelGrid short_of_one = two_by_two();
  short_of_one.panels.pop_back();
  EXPECT_FALSE(write_png_or_warn(short_of_one, dir + "/grid.png", "corner", log));
  EXPECT_NE(log.str().find("corner: warning: no plot (plot: panel grid 2x2 needs 4 panels"), std::string::npos)
      << log.str();
  EXPECT_TRUE(write_png_or_warn(two_by_two(), dir + "/grid.png", "corner", log));
  EXPECT_NE(log.str().find("corner: wrote " + dir + "/grid.png"), std::string::npos) << log.str();
  EXPECT_EQ(files_in(dir), 1);
  fs::remove_all(dir);
}

TEST(Plot, NiceTickStepIsTheSmallest125StepThatFits) {
  EXPECT_DOUBLE_EQ(nice_tick_step(10.0, 5), 2.0);       // exactly 5 intervals of 2
  EXPECT_DOUBLE_EQ(nice_tick_step(1.0, 4), 0.25);       // exactly 4 of 0.25, not 0.5
  EXPECT_DOUBLE_EQ(nice_tick_step(0.19, 5), 0.05);      // 0.038 -> 0.05
  EXPECT_DOUBLE_EQ(nice_tick_step(17000.0, 5), 5000.0);  // 3400 -> 5000
  EXPECT_DOUBLE_EQ(nice_tick_step(2.1e-4, 10), 2.5e-5);  // 2.1e-5 -> 2.5e-5
  EXPECT_DOUBLE_EQ(nice_tick_step(9.5, 1), 10.0);        // the next decade
  // Whatever the span, the step is 1, 2, 2.5 or 5 x 10^k, cuts the span into
  // at most max_intervals intervals, and the next smaller such step would not.
  for (const double span : {0.37, 1.0, 3.3, 11.0, 47.0, 999.0, 1e-7})
    for (int n = 1; n <= 12; ++n) {
      const double step = nice_tick_step(span, n);
      const double decade = std::pow(10.0, std::floor(std::log10(step) + 1e-9));
      const double mantissa = step / decade;
      const std::array<double, 4> nice{1.0, 2.0, 2.5, 5.0};
      const auto at = std::find_if(nice.begin(), nice.end(), [&](double m) { return std::abs(m - mantissa) < 1e-9; });
      ASSERT_NE(at, nice.end()) << "step " << step;
      const double smaller = (at == nice.begin() ? 0.5 : *(at - 1)) * decade;
      EXPECT_LE(span / step, n * (1 + 1e-12)) << span << " " << n;
      EXPECT_GT(span / smaller, n * (1 - 1e-12)) << span << " " << n;
    }
  EXPECT_THROW(nice_tick_step(0.0, 5), std::invalid_argument);
  EXPECT_THROW(nice_tick_step(std::nan(""), 5), std::invalid_argument);
  EXPECT_THROW(nice_tick_step(1.0, 0), std::invalid_argument);
}

TEST(Plot, MaxTicksDrawsAndNegativeIsRefused) {
  const std::string dir = testing::temp_dir();
  LinePlot few_ticks = sine_plot();
  few_ticks.max_ticks = 3;
  write_png(few_ticks, dir + "/few.png");
  EXPECT_EQ(read_png_header(dir + "/few.png").width, 640u);
  few_ticks.max_ticks = -1;
  EXPECT_THROW(write_png(few_ticks, dir + "/negative.png"), std::invalid_argument);
  EXPECT_EQ(files_in(dir), 1);
  fs::remove_all(dir);
}

TEST(Plot, MissingGnuplotThrowsAClearError) {
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path ? old_path : "";
  ::setenv("PATH", "/nonexistent", 1);
  const std::string dir = testing::temp_dir();
  try {
    write_png(sine_plot(), dir + "/line.png");
    ADD_FAILURE() << "expected a PlotError";
  } catch (const PlotError& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot not found"), std::string::npos) << e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(files_in(dir), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rover::io
