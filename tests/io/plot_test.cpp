// PNG plots through gnuplot (io/plot.hpp): files are real PNGs of the asked
// size, written atomically; bad input and bad destinations throw.
#include "io/plot.hpp"

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

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
