// PNG plots through gnuplot (pngcairo terminal): line plots with shaded bands
// (drop curves, Monte Carlo envelopes, fits), grids of line plots in one figure
// (corner plots of a posterior, Foreman-Mackey 2016), bar charts and heat maps
// with contour lines (response surfaces).
//
// Plots are a by-product: callers write their numeric results first and treat
// a PlotError as a warning. A plot is written atomically (temp file in the
// target directory, then rename), so a failure never leaves a partial PNG.
// Labels are printed literally (no gnuplot markup: "v_s" stays "v_s").
#pragma once

#include <optional>
#include <stdexcept>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rover::io {

// gnuplot is missing, the output cannot be written, or gnuplot failed.
class PlotError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The name a figure is drawn under before it is renamed onto its path:
// "<png>" followed by this suffix, its x's random hexadecimal digits.
inline constexpr std::string_view kFigureTemporarySuffix = ".partial-xxxxxxxx";

enum class SeriesStyle { lines, dashed, points, lines_points };

// (Every member has a default, so designated initializers may skip any.)

// A curve y(x). Non-finite values leave a gap. `color` is a gnuplot colour
// name ("black", "dark-red") or "#rrggbb"; empty picks the next default colour.
struct Series {
  std::string label{};  // legend entry; empty = none
  std::vector<double> x{}, y{};
  SeriesStyle style = SeriesStyle::lines;
  std::string color{};
  double line_width = 1.5;
};

// A shaded area between lower(x) and upper(x), drawn under the series.
struct Band {
  std::string label{};
  std::vector<double> x{}, lower{}, upper{};
  std::string color{};
  double opacity = 0.25;  // 0 = invisible, 1 = opaque
};

using AxisRange = std::pair<double, double>;

// A text at a data point (e.g. the input names in a Morris mu*-sigma plane).
struct PointLabel {
  double x = 0.0, y = 0.0;
  std::string text{};
};

struct LinePlot {
  std::string title{}, x_label{}, y_label{};
  std::vector<Series> series{};
  std::vector<Band> bands{};
  std::vector<PointLabel> labels{};
  bool log_x = false, log_y = false;
  std::optional<AxisRange> x_range{}, y_range{};  // automatic when empty
  // Ticks of a linear axis at nice_tick_step(range, max_ticks), the range
  // being x_range / y_range or else the data's; 0 = gnuplot's choice. For
  // small panels, whose automatic tick labels run into each other.
  int max_ticks = 0;
  int width_px = 1000, height_px = 650;
};

// A heat map of z(x, y) on a rectangular grid, with contour lines.
// z is row-major with one row per y: z[j * x.size() + i] = z(x[i], y[j]);
// x and y are strictly increasing.
struct SurfacePlot {
  std::string title{}, x_label{}, y_label{}, z_label{};
  std::vector<double> x{}, y{}, z{};
  bool log_x = false, log_y = false;
  int contour_levels = 10;       // 0 = no contour lines
  std::vector<Series> overlays{};  // e.g. sample points or an optimum, drawn on top
  int width_px = 1000, height_px = 800;
};

// Grouped bars with interval whiskers: for every category (x tick), one bar
// per group (e.g. S1 and ST of each input, with their confidence intervals).
struct BarGroup {
  std::string label{};
  std::vector<double> value{}, lower{}, upper{};  // one per category
};
struct BarPlot {
  std::string title{}, y_label{};
  std::vector<std::string> categories{};
  std::vector<BarGroup> groups{};
  std::optional<AxisRange> y_range{};
  int width_px = 1000, height_px = 650;
};

// Line plots on a rows x cols grid in one figure (gnuplot multiplot), e.g. a
// corner plot: marginal histograms on the diagonal, pairwise scatter below,
// blank cells above. Every panel is drawn as write_png(LinePlot) would draw it
// on its own, nothing carried over from the previous panel; every panel gets
// the same margins, so the axes of a row and of a column line up. A panel's
// width_px and height_px are ignored: the grid's canvas is shared equally.
struct PanelGrid {
  std::string title{};  // over the whole figure; empty = none
  int rows = 1, cols = 1;
  std::vector<std::optional<LinePlot>> panels{};  // row-major, rows * cols; nullopt = blank cell
  int width_px = 1000, height_px = 1000;
};

// Write the plot to `png_path` (replacing it). Throws std::invalid_argument on
// inconsistent data (sizes, unusable colour, empty plot) and PlotError when
// gnuplot is missing or fails or the file cannot be written.
void write_png(const LinePlot& plot, const std::string& png_path);
void write_png(const BarPlot& plot, const std::string& png_path);
void write_png(const SurfacePlot& plot, const std::string& png_path);
// Also refuses a grid whose panel count is not rows * cols, one without a
// panel to draw, and any panel that write_png(LinePlot) would refuse (the
// message names the panel by row and column, counted from 1).
void write_png(const PanelGrid& grid, const std::string& png_path);

// The smallest step of 1, 2, 2.5 or 5 times a power of ten that cuts `span`
// into at most `max_intervals` intervals (Heckbert 1990, "Nice numbers for
// graph labels"). Throws std::invalid_argument unless span > 0 is finite and
// max_intervals >= 1.
double nice_tick_step(double span, int max_intervals);

// "" when gnuplot is on PATH (an executable file of that name in one of its
// directories) and ROVER_PLOT_TIMEOUT, if set, is a time limit in seconds
// (1 to 86400; 300 unless set), else why no plot can be drawn, with the
// remedy ("there is no gnuplot on PATH (<PATH>): install it"): the commands
// check it before any run, where plots are asked for.
std::string plotter_problem();

// For callers whose numbers are already saved: writes the plot and logs
// "<label>: wrote <path>", or logs "<label>: warning: no plot (<why>)" instead
// of throwing, so a missing gnuplot never costs a result. Returns success.
bool write_png_or_warn(const LinePlot& plot, const std::string& png_path, const std::string& label,
                       std::ostream& log);
bool write_png_or_warn(const BarPlot& plot, const std::string& png_path, const std::string& label,
                       std::ostream& log);
bool write_png_or_warn(const PanelGrid& grid, const std::string& png_path, const std::string& label,
                       std::ostream& log);

}  // namespace rover::io
