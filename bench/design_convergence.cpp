// How many runs for the same answer: the error of a Monte Carlo study's
// estimates against the number of runs N, for plain Monte Carlo and for the
// Owen-scrambled Sobol' design (Owen 1997), from `rover montecarlo` result
// files (bench/design_convergence.sh makes them; docs/design_convergence.md
// reports a measurement).
//
// Inputs: R >= 2 replicate files per design (independent seeds, N_max runs
// each) and one reference file (an independent, larger run). For every
// power-of-two prefix N of each replicate (a net for a Sobol' sequence):
//   band  mean(t) and sd(t) (n - 1) of the channel's curves (default B_l z);
//         error = RMS over t of (estimate(t) - reference(t)), divided by the
//         reference's RMS over t of sd(t);
//   QoI   mean and sd of the QoI (default B_l_z_min, the peak compression),
//         error = estimate - reference, divided by the reference's sd of it.
// The error at N is the RMS over the replicates (study/estimators/replicate_error.hpp);
// the replicates' spread about their own mean is the reference-free
// estimate of it (L'Ecuyer and Lemieux 2002). A power law c N^p is fitted to
// each error curve on N >= --fit-min, and gives the runs for --target
// relative error (observed when a measured N already reached it).
//
// Output: <out>.csv (N, then error and spread per design and quantity),
// <out>_band.png and <out>_qoi.png (log-log, with the line 1/sqrt(N): the
// Monte Carlo mean's exact relative RMS error under these normalisations),
// and a summary on standard output.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/estimators/replicate_error.hpp"

namespace {

using namespace rover;
using study::CurveMoments;
using study::PowerLawFit;
using study::ReplicateError;
using study::RunsForError;
using study::SampleMoments;

struct Options {
  std::string reference_path;
  std::vector<std::string> mc_paths, sobol_paths;
  std::string qoi = "B_l_z_min", channel = "B_l_z";
  int n_min = 4, fit_min = 16;
  double target = 0.01;
  std::string out = "results/design_convergence";
  bool plot = true;
};

// One `rover montecarlo` result file: its design and the values analysed.
struct ResultFile {
  std::string path, design, scenario_file, integrator, inputs;
  long long seed = 0;
  std::vector<double> t, qoi;
  Eigen::MatrixXd curves;  // runs x times
};

std::string join(const std::vector<std::string>& words) {
  std::string s;
  for (const std::string& w : words) s += (s.empty() ? "" : ",") + w;
  return s;
}

ResultFile read_result(const std::string& path, const Options& o) {
  const io::Hdf5Reader h5(path);
  if (!h5.has_attribute("/", "study") || h5.attribute_string("/", "study") != "montecarlo")
    throw std::runtime_error(path + ": not a `rover montecarlo` result file");
  for (const std::string& dataset : {"/qoi/" + o.qoi, "/curves/" + o.channel})
    if (!h5.exists(dataset)) throw std::runtime_error(path + ": no " + dataset + " (see the study's qoi and channels)");
  ResultFile f;
  f.path = path;
  f.design = h5.attribute_string("/", "design");
  f.seed = h5.attribute_integer("/", "seed");
  f.scenario_file = h5.attribute_string("/", "scenario_file");
  f.integrator = h5.attribute_string("/", "integrator") + " rtol " + std::to_string(h5.attribute_double("/", "rtol")) +
                 " atol " + std::to_string(h5.attribute_double("/", "atol"));
  f.inputs = join(h5.read_strings("/inputs/names"));
  const std::vector<int> status = h5.read_ints("/samples/status");
  const auto failed = std::count_if(status.begin(), status.end(), [](int s) { return s != 0; });
  if (failed > 0) {
    const auto first = std::find_if(status.begin(), status.end(), [](int s) { return s != 0; }) - status.begin();
    throw std::runtime_error(path + ": " + std::to_string(failed) + " failed runs (the first: sample " +
                             std::to_string(first) + ", " + h5.read_strings("/samples/message")[first] +
                             "); a convergence measurement needs every run");
  }
  f.t = h5.read_doubles("/t");
  f.qoi = h5.read_doubles("/qoi/" + o.qoi);
  f.curves = h5.read_matrix("/curves/" + o.channel);
  if (f.curves.rows() != static_cast<Eigen::Index>(f.qoi.size()) ||
      f.curves.cols() != static_cast<Eigen::Index>(f.t.size()))
    throw std::runtime_error(path + ": /curves/" + o.channel + " is not runs x times");
  return f;
}

// The files must differ only in the design and its seed: same scenario,
// integrator, inputs and output time grid.
void require_same_study(const ResultFile& a, const ResultFile& b) {
  const auto differ = [&](const std::string& what, const std::string& x, const std::string& y) {
    if (x != y) throw std::runtime_error(b.path + ": " + what + " " + y + " differs from " + a.path + ": " + x);
  };
  differ("scenario", a.scenario_file, b.scenario_file);
  differ("integrator", a.integrator, b.integrator);
  differ("inputs", a.inputs, b.inputs);
  if (a.t != b.t) throw std::runtime_error(b.path + ": its time grid /t differs from " + a.path + "'s");
}

// The reference moments and the normalisation of every error.
struct Reference {
  CurveMoments band;
  SampleMoments qoi;
  double band_sd_rms = 0;  // RMS over t of the reference's sd(t)
  int runs = 0;
  std::string design;
};

enum Quantity { kBandMean, kBandSd, kQoiMean, kQoiSd, kQuantities };
constexpr const char* kQuantityKey[kQuantities] = {"band_mean", "band_sd", "qoi_mean", "qoi_sd"};

// Errors of one design, relative (see the top of the file), per quantity and N.
struct DesignErrors {
  std::string name;  // "mc", "sobol"
  std::string design;
  int replicates = 0;
  std::set<long long> seeds;
  std::vector<int> sizes;
  std::vector<ReplicateError> error[kQuantities];
};

DesignErrors design_errors(const std::string& name, const std::string& design,
                           const std::vector<std::string>& paths, const Reference& ref,
                           const std::vector<int>& sizes, const ResultFile& reference_file, const Options& o) {
  const Eigen::Index replicates = static_cast<Eigen::Index>(paths.size()), times = ref.band.mean.size();
  const std::size_t count = sizes.size();
  std::vector<Eigen::MatrixXd> band_mean(count, Eigen::MatrixXd(replicates, times)), band_sd = band_mean;
  std::vector<std::vector<double>> qoi_mean(count, std::vector<double>(paths.size())), qoi_sd = qoi_mean;
  DesignErrors d;
  d.name = name;
  d.design = design;
  d.replicates = static_cast<int>(replicates);
  d.sizes = sizes;
  for (Eigen::Index r = 0; r < replicates; ++r) {
    const ResultFile f = read_result(paths[r], o);
    require_same_study(reference_file, f);
    // Only these designs' prefixes are designs themselves (a Latin hypercube is drawn whole).
    if (f.design != design)
      throw std::runtime_error(f.path + ": design " + f.design + ", not " + design + " (--" + name + ")");
    if (!d.seeds.insert(f.seed).second)
      throw std::runtime_error(f.path + ": seed " + std::to_string(f.seed) + " repeats another replicate's");
    for (std::size_t k = 0; k < count; ++k) {
      const CurveMoments band = study::prefix_curve_moments(f.curves, sizes[k]);
      band_mean[k].row(r) = band.mean.transpose();
      band_sd[k].row(r) = band.sd.transpose();
      const SampleMoments qoi = study::prefix_moments(f.qoi, sizes[k]);
      qoi_mean[k][r] = qoi.mean;
      qoi_sd[k][r] = qoi.sd;
    }
  }
  const auto relative = [](ReplicateError e, double scale) {
    return ReplicateError{e.rms_error / scale, e.spread / scale};
  };
  for (std::size_t k = 0; k < count; ++k) {
    d.error[kBandMean].push_back(relative(study::replicate_error(band_mean[k], ref.band.mean), ref.band_sd_rms));
    d.error[kBandSd].push_back(relative(study::replicate_error(band_sd[k], ref.band.sd), ref.band_sd_rms));
    d.error[kQoiMean].push_back(relative(study::replicate_error(qoi_mean[k], ref.qoi.mean), ref.qoi.sd));
    d.error[kQoiSd].push_back(relative(study::replicate_error(qoi_sd[k], ref.qoi.sd), ref.qoi.sd));
  }
  return d;
}

struct Fits {
  PowerLawFit error, spread;
  RunsForError runs;
};

Fits fit(const DesignErrors& d, Quantity q, const Options& o) {
  std::vector<double> n, error, spread;
  std::vector<int> measured;
  std::vector<double> measured_error;
  for (std::size_t k = 0; k < d.sizes.size(); ++k) {
    measured.push_back(d.sizes[k]);
    measured_error.push_back(d.error[q][k].rms_error);
    if (d.sizes[k] < o.fit_min) continue;
    n.push_back(d.sizes[k]);
    error.push_back(d.error[q][k].rms_error);
    spread.push_back(d.error[q][k].spread);
  }
  Fits f;
  f.error = study::fit_power_law(n, error);
  f.spread = study::fit_power_law(n, spread);
  f.runs = study::runs_for_error(f.error, measured, measured_error, o.target);
  return f;
}

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

std::string describe_runs(const RunsForError& runs) {
  if (std::isinf(runs.fitted)) return "never (the fitted error does not decrease)";
  std::string s = format("%.0f", runs.fitted) + (runs.extrapolated ? " (extrapolated)" : " (within the measured N)");
  s += runs.observed > 0 ? "; observed from N = " + std::to_string(runs.observed) : "; not observed";
  return s;
}

void plot(const std::vector<DesignErrors>& designs, Quantity mean, Quantity sd, const std::string& title,
          const std::string& y_label, const Options& o, const std::string& path) {
  io::LinePlot p;
  p.title = title;
  p.x_label = "runs N";
  p.y_label = y_label;
  p.log_x = p.log_y = true;
  const std::map<std::string, std::pair<std::string, std::string>> colors{{"mc", {"dark-red", "orange"}},
                                                                          {"sobol", {"dark-blue", "dark-cyan"}}};
  for (const DesignErrors& d : designs) {
    for (Quantity q : {mean, sd}) {
      io::Series s;
      s.label = d.design + ", " + (q == mean ? "mean" : "sd");
      for (std::size_t k = 0; k < d.sizes.size(); ++k) {
        s.x.push_back(d.sizes[k]);
        s.y.push_back(d.error[q][k].rms_error);
      }
      s.style = q == mean ? io::SeriesStyle::lines_points : io::SeriesStyle::dashed;
      s.color = q == mean ? colors.at(d.name).first : colors.at(d.name).second;
      p.series.push_back(std::move(s));
    }
  }
  // N^-1/2: with these normalisations, exactly the Monte Carlo mean's RMS error
  // against the exact mean (sd / sqrt(N), pointwise in t for the band).
  const double n0 = designs.front().sizes.front(), n1 = designs.front().sizes.back();
  p.series.push_back({"N^-1/2 (Monte Carlo mean, exact)", {n0, n1}, {1 / std::sqrt(n0), 1 / std::sqrt(n1)},
                      io::SeriesStyle::lines, "black", 1.0});
  if (mean == kQoiMean)
    p.series.push_back({format("%g target", o.target), {n0, n1}, {o.target, o.target}, io::SeriesStyle::dashed,
                        "gray50", 1.0});
  io::write_png_or_warn(p, path, "design_convergence", std::cout);
}

int run(const Options& o) {
  if (o.mc_paths.size() < 2 || o.sobol_paths.size() < 2)
    throw std::invalid_argument("--mc and --sobol need at least 2 replicate files each");
  if (!(o.target > 0)) throw std::invalid_argument("--target must be positive");

  const ResultFile reference_file = read_result(o.reference_path, o);
  Reference ref;
  ref.runs = static_cast<int>(reference_file.qoi.size());
  ref.design = reference_file.design;
  ref.band = study::prefix_curve_moments(reference_file.curves, ref.runs);
  ref.qoi = study::prefix_moments(reference_file.qoi, ref.runs);
  ref.band_sd_rms = std::sqrt(ref.band.sd.squaredNorm() / static_cast<double>(ref.band.sd.size()));
  if (!(ref.band_sd_rms > 0 && ref.qoi.sd > 0))
    throw std::runtime_error(o.reference_path + ": the reference's sd is zero, nothing to normalise by");

  // N_max: the largest power of two every replicate holds; the reference must be larger.
  std::size_t smallest = std::numeric_limits<std::size_t>::max();
  for (const auto* paths : {&o.mc_paths, &o.sobol_paths})
    for (const std::string& path : *paths) smallest = std::min(smallest, io::Hdf5Reader(path).shape("/qoi/" + o.qoi).at(0));
  const std::vector<int> sizes =
      study::power_of_two_sizes(std::max(o.n_min, 2), static_cast<int>(std::min<std::size_t>(smallest, 1 << 30)));
  if (std::count_if(sizes.begin(), sizes.end(), [&](int n) { return n >= o.fit_min; }) < 2)
    throw std::invalid_argument("--fit-min " + std::to_string(o.fit_min) + " leaves fewer than 2 sizes up to N = " +
                                std::to_string(sizes.back()) + " to fit");
  if (ref.runs <= sizes.back())
    throw std::invalid_argument(o.reference_path + ": the reference has " + std::to_string(ref.runs) +
                                " runs, not more than the replicates' " + std::to_string(sizes.back()));
  const std::vector<DesignErrors> designs{
      design_errors("mc", "monte_carlo", o.mc_paths, ref, sizes, reference_file, o),
      design_errors("sobol", "sobol", o.sobol_paths, ref, sizes, reference_file, o)};
  for (const DesignErrors& d : designs)
    if (d.design == ref.design && d.seeds.count(reference_file.seed) > 0)
      throw std::runtime_error("a " + d.name + " replicate has the reference's design and seed (" +
                               std::to_string(reference_file.seed) + "); the reference must be independent");

  // Fits, the reference's own error, the runs for the target.
  std::ostringstream summary;
  summary << "Reference: " << o.reference_path << " (" << ref.design << ", N = " << ref.runs << ", seed "
          << reference_file.seed << "): " << o.qoi << " mean " << format("%.6g", ref.qoi.mean) << ", sd "
          << format("%.4g", ref.qoi.sd) << "; " << o.channel << " band: RMS over t of sd(t) "
          << format("%.4g", ref.band_sd_rms) << ".\n"
          << "Errors: RMS over " << designs[0].replicates << " (mc) and " << designs[1].replicates
          << " (sobol) replicates of (estimate - reference); band errors are RMS over t and divided by the\n"
          << "reference's RMS sd(t), QoI errors divided by the reference's QoI sd. Power laws fitted on N >= "
          << o.fit_min << ".\n";
  const std::string names[kQuantities] = {o.channel + " band mean(t)", o.channel + " band sd(t)", o.qoi + " mean",
                                          o.qoi + " sd"};
  std::vector<std::vector<Fits>> fits(designs.size());
  for (std::size_t i = 0; i < designs.size(); ++i)
    for (int q = 0; q < kQuantities; ++q) fits[i].push_back(fit(designs[i], static_cast<Quantity>(q), o));
  for (int q = 0; q < kQuantities; ++q) {
    summary << names[q] << ":\n";
    for (std::size_t i = 0; i < designs.size(); ++i) {
      const Fits& f = fits[i][q];
      summary << "  " << designs[i].design << ": error " << format("%.3g", f.error.coefficient) << " N^"
              << format("%.3f", f.error.exponent) << " (+- " << format("%.3f", f.error.exponent_se)
              << "), spread N^" << format("%.3f", f.spread.exponent) << "; runs for "
              << format("%g", 100 * o.target) << " %: " << describe_runs(f.runs) << "\n";
    }
    // The reference's own error: its design's spread fit (reference-free) at its N.
    for (std::size_t i = 0; i < designs.size(); ++i)
      if (designs[i].design == ref.design) {
        const double own = fits[i][q].spread.error_at(ref.runs);
        const double last = designs[i].error[q].back().rms_error;
        summary << "  reference's own error (the " << ref.design << " spread fit at N = " << ref.runs
                << "): " << format("%.3g", own) << ", " << format("%.2g", own / last)
                << " of the smallest measured error (" << designs[i].design << ", N = " << designs[i].sizes.back()
                << ")" << (own > 0.5 * last ? ": TOO LARGE, the errors at large N measure the reference; use a larger one" : "")
                << "\n";
      }
  }
  std::cout << summary.str();

  // The table.
  std::vector<std::string> header{"N"};
  std::vector<std::vector<double>> columns(1);
  for (int n : sizes) columns[0].push_back(n);
  for (const DesignErrors& d : designs)
    for (int q = 0; q < kQuantities; ++q) {
      header.push_back(d.name + "_" + kQuantityKey[q] + "_error");
      header.push_back(d.name + "_" + kQuantityKey[q] + "_spread");
      columns.emplace_back();
      columns.emplace_back();
      for (const ReplicateError& e : d.error[q]) {
        columns[columns.size() - 2].push_back(e.rms_error);
        columns.back().push_back(e.spread);
      }
    }
  std::string comment = "Error against the number of runs N (bench/design_convergence.cpp)\n" + summary.str() +
                        "Columns: <design>_<quantity>_error = RMS over replicates of (estimate - reference), "
                        "<design>_<quantity>_spread = replicate sd (reference-free), both relative as above.\n"
                        "mc files: " + join(o.mc_paths) + "\nsobol files: " + join(o.sobol_paths);
  io::write_csv(o.out + ".csv", header, columns, comment);
  std::cout << "design_convergence: wrote " << o.out << ".csv\n";
  if (o.plot) {
    plot(designs, kBandMean, kBandSd, o.channel + " band: error of mean(t) and sd(t) against N",
         "RMS error / RMS sd(t) of the reference", o, o.out + "_band.png");
    plot(designs, kQoiMean, kQoiSd, o.qoi + ": error of its mean and sd against N", "RMS error / sd of the reference",
         o, o.out + "_qoi.png");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Error of the Monte Carlo band and QoI moments against N, plain Monte Carlo against Sobol'"};
  app.add_option("--reference", o.reference_path, "Reference result file (an independent large run)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--mc", o.mc_paths, "Monte Carlo replicate result files (independent seeds)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--sobol", o.sobol_paths, "Sobol' replicate result files (independent seeds)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--qoi", o.qoi, "QoI whose mean and sd are measured")->capture_default_str();
  app.add_option("--channel", o.channel, "Channel whose band is measured")->capture_default_str();
  app.add_option("--n-min", o.n_min, "Smallest prefix N")->capture_default_str()->check(CLI::Range(2, 1 << 30));
  app.add_option("--fit-min", o.fit_min, "Smallest N in the power-law fits")->capture_default_str();
  app.add_option("--target", o.target, "Relative error for the runs-needed estimate")->capture_default_str();
  app.add_option("--out", o.out, "Output prefix: <out>.csv, <out>_band.png, <out>_qoi.png")->capture_default_str();
  app.add_flag("!--no-plot", o.plot, "Do not write the PNGs");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::cerr << "design_convergence: error: " << e.what() << "\n";
    return 1;
  }
}
