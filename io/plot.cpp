// PNG plots through gnuplot: the data go into inline data blocks of one
// script file, gnuplot renders into a temp file next to the target, and the
// temp file is renamed onto the target only when gnuplot succeeded. A panel
// grid is one script too: `set multiplot layout`, and before every panel a
// `reset`, so no setting of one panel leaks into the next.
#include "io/plot.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/output_target.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

// A gnuplot single-quoted string: only '' is special there (no escapes, no
// backquote or macro substitution); line breaks become spaces.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') out += "''";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "'";
}

// A POSIX shell single-quoted word.
std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g", value);
  return buffer;
}

// "lc rgb '<colour>' " or nothing; refuses anything but a name or #rrggbb.
std::string color_spec(const std::string& color) {
  if (color.empty()) return "";
  for (const char c : color) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '#' || c == '-';
    if (!ok) throw std::invalid_argument("plot: unusable colour '" + color + "'");
  }
  return "lc rgb " + quoted(color) + " ";
}

std::string title_spec(const std::string& label) {
  return label.empty() ? "notitle" : "title " + quoted(label);
}

void check_size(const std::string& context, const std::string& what, std::size_t size,
                std::size_t expected) {
  if (size != expected)
    throw std::invalid_argument(context + what + " has " + std::to_string(size) +
                                " values, expected " + std::to_string(expected));
}

void check_canvas(int width_px, int height_px) {
  if (width_px < 100 || height_px < 100 || width_px > 20000 || height_px > 20000)
    throw std::invalid_argument("plot: canvas " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + " px out of range [100, 20000]");
}

// A data block of rows; a row with a non-finite value becomes a blank line,
// which gnuplot draws as a gap.
void write_block(std::ostream& out, const std::string& name,
                 const std::vector<const std::vector<double>*>& columns) {
  out << name << " << EOD\n";
  const std::size_t rows = columns.front()->size();
  for (std::size_t i = 0; i < rows; ++i) {
    bool finite = true;
    for (const auto* column : columns) finite = finite && std::isfinite((*column)[i]);
    if (finite) {
      for (std::size_t j = 0; j < columns.size(); ++j)
        out << (j ? " " : "") << number((*columns[j])[i]);
    }
    out << "\n";
  }
  out << "EOD\n";
}

std::string series_spec(const Series& s) {
  std::string style;
  switch (s.style) {
    case SeriesStyle::lines: style = "with lines dt solid "; break;
    case SeriesStyle::dashed: style = "with lines dt 2 "; break;
    case SeriesStyle::points: style = "with points pt 7 ps 0.6 "; break;
    case SeriesStyle::lines_points: style = "with linespoints pt 7 ps 0.6 "; break;
  }
  return style + "lw " + number(s.line_width) + " " + color_spec(s.color) + title_spec(s.label);
}

// The pngcairo terminal writing `output`.
void write_terminal(std::ostream& out, const std::string& output, int width_px, int height_px) {
  out << "set terminal pngcairo size " << width_px << "," << height_px
      << " noenhanced font 'sans,11'\n"
      << "set output " << quoted(output) << "\n"
      << "set encoding utf8\n";
}

void write_axes(std::ostream& out, const std::string& title, const std::string& x_label,
                const std::string& y_label, bool log_x, bool log_y) {
  if (!title.empty()) out << "set title " << quoted(title) << "\n";
  out << "set xlabel " << quoted(x_label) << "\n"
      << "set ylabel " << quoted(y_label) << "\n";
  if (log_x) out << "set logscale x\n";
  if (log_y) out << "set logscale y\n";
}

void write_common(std::ostream& out, const std::string& output, int width_px, int height_px,
                  const std::string& title, const std::string& x_label,
                  const std::string& y_label, bool log_x, bool log_y) {
  write_terminal(out, output, width_px, height_px);
  write_axes(out, title, x_label, y_label, log_x, log_y);
}

// Refuses a line plot with inconsistent data, an unusable colour or nothing to
// draw, before any script is written; `context` starts every message
// ("plot: <path>: " or "plot: <path>: panel (row 1, column 2): ").
void check_line_plot(const LinePlot& plot, const std::string& context) {
  bool any_data = false;
  for (const Series& s : plot.series) {
    check_size(context, "series '" + s.label + "' y", s.y.size(), s.x.size());
    any_data = any_data || !s.x.empty();
  }
  for (const Band& b : plot.bands) {
    check_size(context, "band '" + b.label + "' lower", b.lower.size(), b.x.size());
    check_size(context, "band '" + b.label + "' upper", b.upper.size(), b.x.size());
    if (!(b.opacity >= 0.0 && b.opacity <= 1.0))
      throw std::invalid_argument(context + "band '" + b.label + "' opacity " + number(b.opacity) +
                                  " not in [0, 1]");
    any_data = any_data || !b.x.empty();
  }
  if (!any_data) throw std::invalid_argument(context + "nothing to plot");
  if (plot.max_ticks < 0)
    throw std::invalid_argument(context + "max_ticks " + std::to_string(plot.max_ticks) + " < 0");
  for (const Series& s : plot.series) static_cast<void>(color_spec(s.color));
  for (const Band& b : plot.bands) static_cast<void>(color_spec(b.color));
}

// The smallest and largest finite value of some columns; nullopt when none.
std::optional<AxisRange> extent(const std::vector<const std::vector<double>*>& columns) {
  std::optional<AxisRange> range;
  for (const auto* column : columns)
    for (const double v : *column)
      if (std::isfinite(v))
        range = range ? AxisRange{std::min(range->first, v), std::max(range->second, v)} : AxisRange{v, v};
  return range;
}

// "set <axis>tics <step>" for at most max_ticks intervals over `range`
// (or, when empty, over the data); nothing for a log axis or an empty span.
void write_tick_step(std::ostream& out, const std::string& axis, int max_ticks, bool log_scale,
                     const std::optional<AxisRange>& range,
                     const std::vector<const std::vector<double>*>& columns) {
  if (max_ticks <= 0 || log_scale) return;
  const std::optional<AxisRange> over = range ? range : extent(columns);
  if (!over) return;
  const double span = std::abs(over->second - over->first);
  if (span > 0.0 && std::isfinite(span))
    out << "set " << axis << "tics " << number(nice_tick_step(span, max_ticks)) << "\n";
}

// One line plot after the terminal: axes, data blocks and the plot command.
// Data blocks are "$<block_prefix>band<k>" and "$<block_prefix>series<k>", so
// plots of one script with distinct prefixes never share a block.
void write_line_plot(std::ostream& out, const LinePlot& plot, const std::string& block_prefix) {
  write_axes(out, plot.title, plot.x_label, plot.y_label, plot.log_x, plot.log_y);
  const bool any_label =
      std::any_of(plot.series.begin(), plot.series.end(), [](const Series& s) { return !s.label.empty(); }) ||
      std::any_of(plot.bands.begin(), plot.bands.end(), [](const Band& b) { return !b.label.empty(); });
  out << "set grid\n" << (any_label ? "set key top right opaque box\n" : "unset key\n");
  if (plot.x_range)
    out << "set xrange [" << number(plot.x_range->first) << ":" << number(plot.x_range->second)
        << "]\n";
  if (plot.y_range)
    out << "set yrange [" << number(plot.y_range->first) << ":" << number(plot.y_range->second)
        << "]\n";
  std::vector<const std::vector<double>*> xs, ys;
  for (const Series& s : plot.series) {
    xs.push_back(&s.x);
    ys.push_back(&s.y);
  }
  for (const Band& b : plot.bands) {
    xs.push_back(&b.x);
    ys.insert(ys.end(), {&b.lower, &b.upper});
  }
  write_tick_step(out, "x", plot.max_ticks, plot.log_x, plot.x_range, xs);
  write_tick_step(out, "y", plot.max_ticks, plot.log_y, plot.y_range, ys);
  for (const PointLabel& l : plot.labels)
    if (std::isfinite(l.x) && std::isfinite(l.y))
      out << "set label " << quoted(l.text) << " at " << number(l.x) << "," << number(l.y)
          << " offset 0.6,0.6 font ',10'\n";
  std::vector<std::string> items;
  for (std::size_t k = 0; k < plot.bands.size(); ++k) {
    const Band& b = plot.bands[k];
    if (b.x.empty()) continue;
    const std::string name = "$" + block_prefix + "band" + std::to_string(k);
    write_block(out, name, {&b.x, &b.lower, &b.upper});
    items.push_back(name + " using 1:2:3 with filledcurves fs transparent solid " +
                    number(b.opacity) + " noborder " + color_spec(b.color) + title_spec(b.label));
  }
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const Series& s = plot.series[k];
    if (s.x.empty()) continue;
    const std::string name = "$" + block_prefix + "series" + std::to_string(k);
    write_block(out, name, {&s.x, &s.y});
    items.push_back(name + " using 1:2 " + series_spec(s));
  }
  out << "plot ";
  for (std::size_t k = 0; k < items.size(); ++k) out << (k ? ", \\\n     " : "") << items[k];
  out << "\n";
}

// A new file "<stem><random>" (mode 0666 less the umask, like any output),
// removed when it goes out of scope unless released.
class TempFile {
 public:
  // Throws PlotError naming `purpose` when the file cannot be created.
  TempFile(const std::string& stem, const std::string& purpose) {
    std::random_device entropy;
    for (int attempt = 0; attempt < 100; ++attempt) {
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(entropy()));
      const std::string candidate = stem + suffix;
      const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0) {
        ::close(fd);
        path_ = candidate;
        return;
      }
      if (errno != EEXIST)
        throw PlotError("plot: cannot create " + purpose + " '" + candidate + "': " +
                        std::strerror(errno));
    }
    throw PlotError("plot: cannot create a unique " + purpose + " '" + stem + "*'");
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (!path_.empty()) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }
  const std::string& path() const { return path_; }
  void release() { path_.clear(); }

 private:
  std::string path_;
};

// Whether the file ends as every complete PNG does, in its IEND chunk (gnuplot
// exits 0 after a write the disk had no room for).
bool ends_in_png_end_chunk(const std::string& path) {
  static constexpr char kEndChunk[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', '\xAE', '\x42', '\x60', '\x82'};
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in || in.tellg() < static_cast<std::streamoff>(sizeof kEndChunk)) return false;
  in.seekg(-static_cast<std::streamoff>(sizeof kEndChunk), std::ios::end);
  char tail[sizeof kEndChunk] = {};
  return static_cast<bool>(in.read(tail, sizeof tail)) && std::equal(tail, tail + sizeof tail, kEndChunk);
}

// How long one figure may take to render (unless the environment variable
// ROVER_PLOT_TIMEOUT gives another whole number of seconds), and how long a
// plotter that ignores SIGTERM then has before SIGKILL; timeout(1)'s
// statuses for each.
constexpr const char* kPlotterTimeLimitVariable = "ROVER_PLOT_TIMEOUT";
constexpr int kPlotterTimeLimit_s = 300;
constexpr int kMaxPlotterTimeLimit_s = 86'400;
constexpr int kPlotterKillGrace_s = 5;
constexpr int kTimedOutStatus = 124;
constexpr int kKilledStatus = 128 + SIGKILL;

// Why ROVER_PLOT_TIMEOUT cannot be read, or empty (also when it is unset).
std::string plotter_time_limit_problem() {
  const char* text = std::getenv(kPlotterTimeLimitVariable);
  if (text == nullptr) return "";
  const std::string value(text);
  int seconds = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), seconds);
  if (!value.empty() && error == std::errc() && end == value.data() + value.size() && seconds >= 1 &&
      seconds <= kMaxPlotterTimeLimit_s)
    return "";
  return "the environment variable " + std::string(kPlotterTimeLimitVariable) + "='" + value +
         "', which limits its time, is not a whole number of seconds from 1 to " +
         std::to_string(kMaxPlotterTimeLimit_s) + ": unset it (then " + std::to_string(kPlotterTimeLimit_s) +
         " s) or give such a number";
}

int plotter_time_limit_s() {
  if (const std::string problem = plotter_time_limit_problem(); !problem.empty()) throw PlotError("plot: " + problem);
  const char* text = std::getenv(kPlotterTimeLimitVariable);
  return text == nullptr ? kPlotterTimeLimit_s : std::atoi(text);
}

// Writes the script that `script_for(output path)` returns, runs gnuplot on
// it, and moves the output onto png_path only when gnuplot succeeded.
void render(const std::string& png_path,
            const std::function<std::string(const std::string&)>& script_for) {
  if (const OutputTarget target = inspect_output(png_path, OutputFormat::kSeekable); !target.refusal.empty())
    throw PlotError("plot: " + png_path + ": " + target.refusal);
  TempFile partial(png_path + ".partial-", "plot file");
  const TempFile script((fs::temp_directory_path() / "rover-plot-").string(), "gnuplot script");
  {
    std::ofstream out(script.path());
    out << script_for(partial.path());
    if (!out) throw PlotError("plot: cannot write gnuplot script '" + script.path() + "'");
  }
  // A plotter that never returns (a broken installation, a wrapper waiting
  // on a display) is ended (timeout(1), SIGTERM then SIGKILL), not waited
  // for forever; rover's own figures render in seconds.
  const int time_limit_s = plotter_time_limit_s();
  const std::string command = "timeout -k " + std::to_string(kPlotterKillGrace_s) + " " +
                              std::to_string(time_limit_s) + " gnuplot " + shell_quoted(script.path()) + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw PlotError("plot: cannot run gnuplot: " + std::string(std::strerror(errno)));
  std::string log;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) log += buffer;
  const int status = ::pclose(pipe);
  const int code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  if (code == 127)
    throw PlotError("plot: gnuplot not found on PATH (install gnuplot with the pngcairo "
                    "terminal); " + png_path + " not written");
  if (code == kTimedOutStatus || code == kKilledStatus)
    throw PlotError("plot: gnuplot did not finish within " + std::to_string(time_limit_s) + " s and was ended; " +
                    png_path + " not written (check the gnuplot on PATH, or give more time: " +
                    kPlotterTimeLimitVariable + "=<seconds>)");
  if (code != 0)
    throw PlotError("plot: gnuplot failed (exit " + std::to_string(code) + ") writing " +
                    png_path + ": " + log);
  std::error_code error;
  const auto size = fs::file_size(partial.path(), error);
  const std::string why = log.empty() ? "gnuplot said nothing: is the disk full?" : log;
  if (error || size == 0) throw PlotError("plot: gnuplot wrote nothing for " + png_path + " (" + why + ")");
  if (!ends_in_png_end_chunk(partial.path()))
    throw PlotError("plot: gnuplot wrote " + std::to_string(size) + " bytes of " + png_path +
                    " and no PNG end chunk: an incomplete image, not kept (" + why + ")");
  // The temporary file was created private (0600); a new plot is for everyone
  // to read, one that replaces a plot keeps that file's permissions.
  const fs::file_status replaced = fs::status(png_path, error);
  const fs::perms perms = fs::is_regular_file(replaced) ? replaced.permissions() & fs::perms::all
                                                        : fs::perms::owner_read | fs::perms::owner_write |
                                                              fs::perms::group_read | fs::perms::others_read;
  fs::permissions(partial.path(), perms, error);
  fs::rename(partial.path(), png_path, error);
  if (error)
    throw PlotError("plot: cannot rename '" + partial.path() + "' to " + png_path + ": " +
                    error.message());
  partial.release();
}

}  // namespace

std::string plotter_problem() {
  if (std::string problem = plotter_time_limit_problem(); !problem.empty()) return problem;
  const char* path = std::getenv("PATH");
  std::stringstream directories(path ? path : "");
  for (std::string dir; std::getline(directories, dir, ':');) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/gnuplot";
    std::error_code error;
    if (fs::is_regular_file(candidate, error) && ::access(candidate.c_str(), X_OK) == 0) return "";
  }
  return "there is no gnuplot on PATH (" + std::string(path ? path : "unset") + "): install it";
}

double nice_tick_step(double span, int max_intervals) {
  if (!(span > 0.0 && std::isfinite(span)) || max_intervals < 1)
    throw std::invalid_argument("nice_tick_step: needs a finite span > 0 and max_intervals >= 1, got " +
                                number(span) + " and " + std::to_string(max_intervals));
  const double smallest = span / max_intervals;
  const double decade = std::pow(10.0, std::floor(std::log10(smallest)));
  // (The relative slack keeps an exact fit, span 1 in 4 steps of 0.25, from
  // rounding up to the next step.)
  for (const double mantissa : {1.0, 2.0, 2.5, 5.0})
    if (mantissa * decade >= smallest * (1.0 - 1e-12)) return mantissa * decade;
  return 10.0 * decade;
}

void write_png(const LinePlot& plot, const std::string& png_path) {
  check_canvas(plot.width_px, plot.height_px);
  check_line_plot(plot, "plot: " + png_path + ": ");
  render(png_path, [&](const std::string& output) {
    std::ostringstream out;
    write_terminal(out, output, plot.width_px, plot.height_px);
    write_line_plot(out, plot, "");
    return out.str();
  });
}

void write_png(const PanelGrid& grid, const std::string& png_path) {
  check_canvas(grid.width_px, grid.height_px);
  if (grid.rows < 1 || grid.cols < 1)
    throw std::invalid_argument("plot: panel grid " + std::to_string(grid.rows) + "x" +
                                std::to_string(grid.cols) + " needs at least one row and one column");
  const auto cells = static_cast<std::size_t>(grid.rows) * static_cast<std::size_t>(grid.cols);
  if (grid.panels.size() != cells)
    throw std::invalid_argument("plot: panel grid " + std::to_string(grid.rows) + "x" +
                                std::to_string(grid.cols) + " needs " + std::to_string(cells) +
                                " panels (row-major, nullopt for a blank cell), got " +
                                std::to_string(grid.panels.size()));
  if (std::none_of(grid.panels.begin(), grid.panels.end(),
                   [](const std::optional<LinePlot>& panel) { return panel.has_value(); }))
    throw std::invalid_argument("plot: panel grid for " + png_path + " has only blank cells");
  const auto cell_name = [&](std::size_t k) {
    return "panel (row " + std::to_string(k / static_cast<std::size_t>(grid.cols) + 1) + ", column " +
           std::to_string(k % static_cast<std::size_t>(grid.cols) + 1) + ")";
  };
  for (std::size_t k = 0; k < cells; ++k)
    if (grid.panels[k]) check_line_plot(*grid.panels[k], "plot: " + png_path + ": " + cell_name(k) + ": ");

  render(png_path, [&](const std::string& output) {
    std::ostringstream out;
    write_terminal(out, output, grid.width_px, grid.height_px);
    out << "set multiplot layout " << grid.rows << "," << grid.cols << " rowsfirst";
    if (!grid.title.empty()) out << " title " << quoted(grid.title) << " font ',13'";
    out << "\n";
    for (std::size_t k = 0; k < cells; ++k) {
      if (!grid.panels[k]) {
        out << "set multiplot next\n";
        continue;
      }
      // Back to the defaults (terminal, output and layout stay), then margins
      // in character cells, the same for every panel, so the axes line up.
      out << "reset\n"
          << "set lmargin 11\nset rmargin 2\nset bmargin 3.5\nset tmargin 3\n";
      write_line_plot(out, *grid.panels[k], std::string("panel") + std::to_string(k) + "_");
    }
    out << "unset multiplot\n";
    return out.str();
  });
}

void write_png(const SurfacePlot& plot, const std::string& png_path) {
  check_canvas(plot.width_px, plot.height_px);
  const std::size_t nx = plot.x.size(), ny = plot.y.size();
  if (nx < 2 || ny < 2)
    throw std::invalid_argument("plot: surface needs at least 2 x and 2 y values, got " +
                                std::to_string(nx) + " and " + std::to_string(ny));
  check_size("plot: ", "surface z", plot.z.size(), nx * ny);
  for (const auto* axis : {&plot.x, &plot.y})
    for (std::size_t i = 1; i < axis->size(); ++i)
      if (!((*axis)[i] > (*axis)[i - 1]))
        throw std::invalid_argument("plot: surface axes must be strictly increasing");
  if (plot.contour_levels < 0)
    throw std::invalid_argument("plot: contour_levels must be >= 0");
  for (const Series& s : plot.overlays)
    check_size("plot: ", "overlay '" + s.label + "' y", s.y.size(), s.x.size());

  render(png_path, [&](const std::string& output) {
    std::ostringstream out;
    write_common(out, output, plot.width_px, plot.height_px, plot.title, plot.x_label,
                 plot.y_label, plot.log_x, plot.log_y);
    out << "set cblabel " << quoted(plot.z_label) << "\n"
        << "set view map\n"
        << "set pm3d at b corners2color mean\n"
        << "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', "
           "4 '#fde725')\n"
        << "set xrange [" << number(plot.x.front()) << ":" << number(plot.x.back()) << "]\n"
        << "set yrange [" << number(plot.y.front()) << ":" << number(plot.y.back()) << "]\n"
        << "set key top left opaque box\n";
    if (plot.contour_levels > 0)
      out << "set contour base\nset cntrparam levels auto " << plot.contour_levels
          << "\nset cntrlabel onecolor\n";
    // Grid rows, one scan per y, separated by blank lines.
    out << "$grid << EOD\n";
    for (std::size_t j = 0; j < ny; ++j) {
      for (std::size_t i = 0; i < nx; ++i) {
        const double z = plot.z[j * nx + i];
        out << number(plot.x[i]) << " " << number(plot.y[j]) << " "
            << (std::isfinite(z) ? number(z) : std::string("NaN")) << "\n";
      }
      out << "\n";
    }
    out << "EOD\n";
    std::vector<std::string> items{"$grid using 1:2:3 with pm3d notitle"};
    if (plot.contour_levels > 0)
      items.push_back("$grid using 1:2:3 with lines nosurface lc rgb 'black' lw 0.8 notitle");
    for (std::size_t k = 0; k < plot.overlays.size(); ++k) {
      const Series& s = plot.overlays[k];
      if (s.x.empty()) continue;
      const std::string name = "$overlay" + std::to_string(k);
      write_block(out, name, {&s.x, &s.y});
      items.push_back(name + " using 1:2:(0) " + series_spec(s) + " nocontour");
    }
    out << "splot ";
    for (std::size_t k = 0; k < items.size(); ++k) out << (k ? ", \\\n      " : "") << items[k];
    out << "\n";
    return out.str();
  });
}

void write_png(const BarPlot& plot, const std::string& png_path) {
  check_canvas(plot.width_px, plot.height_px);
  const std::size_t n = plot.categories.size();
  if (n == 0 || plot.groups.empty()) throw std::invalid_argument("plot: nothing to plot for " + png_path);
  for (const BarGroup& g : plot.groups) {
    check_size("plot: ", "bar group '" + g.label + "'", g.value.size(), n);
    check_size("plot: ", "bar group '" + g.label + "' lower", g.lower.size(), n);
    check_size("plot: ", "bar group '" + g.label + "' upper", g.upper.size(), n);
  }
  render(png_path, [&](const std::string& output) {
    std::ostringstream out;
    write_common(out, output, plot.width_px, plot.height_px, plot.title, "", plot.y_label, false, false);
    out << "set grid ytics\nset key top right opaque box\n"
        << "set style data histograms\nset style histogram errorbars gap 1.5 lw 1.2\n"
        << "set style fill solid 0.6 border -1\nset boxwidth 0.9\nset xtics rotate by -30\n";
    if (plot.y_range)
      out << "set yrange [" << number(plot.y_range->first) << ":" << number(plot.y_range->second) << "]\n";
    std::vector<std::string> items;
    for (std::size_t k = 0; k < plot.groups.size(); ++k) {
      const BarGroup& g = plot.groups[k];
      const std::string name = "$bars" + std::to_string(k);
      out << name << " << EOD\n";
      for (std::size_t i = 0; i < n; ++i) {
        std::string category = plot.categories[i];
        for (char& c : category)
          if (std::isspace(static_cast<unsigned char>(c)) || c == '"') c = '_';
        const auto value = [](double v) { return std::isfinite(v) ? number(v) : std::string("NaN"); };
        out << '"' << category << "\" " << value(g.value[i]) << " " << value(g.lower[i]) << " " << value(g.upper[i])
            << "\n";
      }
      out << "EOD\n";
      items.push_back(name + " using 2:3:4" + (k == 0 ? std::string(":xtic(1)") : std::string()) + " " +
                      title_spec(g.label));
    }
    out << "plot ";
    for (std::size_t k = 0; k < items.size(); ++k) out << (k ? ", \\\n     " : "") << items[k];
    out << "\n";
    return out.str();
  });
}

namespace {

template <class Plot>
bool write_or_warn(const Plot& plot, const std::string& png_path, const std::string& label, std::ostream& log) {
  try {
    write_png(plot, png_path);
    log << label << ": wrote " << png_path << "\n";
    return true;
  } catch (const std::exception& e) {
    log << label << ": warning: no plot (" << e.what() << ")\n";
    return false;
  }
}

}  // namespace

bool write_png_or_warn(const LinePlot& plot, const std::string& png_path, const std::string& label,
                       std::ostream& log) {
  return write_or_warn(plot, png_path, label, log);
}

bool write_png_or_warn(const BarPlot& plot, const std::string& png_path, const std::string& label,
                       std::ostream& log) {
  return write_or_warn(plot, png_path, label, log);
}

bool write_png_or_warn(const PanelGrid& grid, const std::string& png_path, const std::string& label,
                       std::ostream& log) {
  return write_or_warn(grid, png_path, label, log);
}

}  // namespace rover::io
