// The result file and the console report of a calibration fit
// (calibration_checked_fit.hpp; the layout is in docs/results_format.md).
#include <cmath>
#include <cstdio>
#include <ostream>

#include "study/studies/calibration_checked_fit.hpp"
#include "io/checkpoint.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

std::vector<double> row_major(const Eigen::MatrixXd& m) {
  std::vector<double> v;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) v.push_back(m(i, j));
  return v;
}

std::vector<std::string> fitted_names(const CalibrationStudy& s) {
  std::vector<std::string> names;
  for (const FitParameter& f : s.fit) names.push_back(f.name);
  return names;
}

void write_history(const CalibrationFitResult& r, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  const std::size_t K = s.datasets.size(), row = HistoryLayout(s).width();
  std::vector<std::string> columns = fitted_names(s);
  for (std::size_t k = 0; k < K; ++k) columns.push_back(K == 1 ? "time_offset" : "time_offset[" + std::to_string(k) + "]");
  columns.insert(columns.end(), {"rms", "objective", "status"});
  h5.write("/history", r.history.rows, r.history.rows.size() / row, row);
  h5.write("/history_columns", columns);
  h5.write("/history_start", r.history.start);
  std::vector<std::string> messages = r.history.messages;
  messages.insert(messages.end(), r.checked.integrator_actions.begin(), r.checked.integrator_actions.end());
  h5.write("/messages", messages);
}

void write_best(const CalibrationFitResult& r, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  const CheckedFit& c = r.checked;
  h5.write("/best/values", c.fit.values);
  h5.write("/best/names", fitted_names(s));
  h5.write("/best/time_offset", c.fit.offsets);
  h5.write("/best/rms", std::vector<double>{r.best_rms_m});
  h5.write("/best/residual_lag1", r.curve_residual_lag1);
  h5.attribute("/best/residual_lag1", "meaning",
               std::string("lag-1 autocorrelation of each curve's residuals at the best fit; independent noise "
                           "gives 0 +- 1/sqrt(points), a model that does not follow the curve near 1"));
  h5.attribute("/best", "converged", static_cast<long long>(c.fit.converged));
  h5.attribute("/best", "stop_reason", std::string(least_squares_stop_name(c.fit.stop)));
  h5.attribute("/best", "stop_message", c.fit.message);
  h5.attribute("/best", "intervals_valid", static_cast<long long>(r.trusted));
  h5.attribute("/best", "not_valid_because", r.not_valid_because);
  h5.attribute("/best", "iterations", static_cast<long long>(c.fit.iterations));
  h5.attribute("/best", "integrator", describe_integrator(c.study.integrator));
  if (!c.shift.ok && !c.shift.message.empty()) h5.attribute("/best", "integration_check", c.shift.message);
  if (c.shift.ok) {
    h5.write("/best/integration_shift", c.shift.shift_se);
    h5.attribute("/best/integration_shift", "meaning",
                 std::string("shift of each fitted parameter, in its standard errors, when the best curves are run "
                             "with the reference integrator (") +
                     describe_integrator(c.study.integration_check.reference) + ")");
  }
  if (c.probe.ok) {
    const Eigen::MatrixXd& d = c.probe.delta_chi2;
    h5.write("/best/probe_delta_chi2", row_major(d), static_cast<std::size_t>(d.rows()), static_cast<std::size_t>(d.cols()));
    h5.write("/best/probe_multiples", probe_multiples());
  }
}

void write_uncertainty(const GaussNewtonResult& gn, io::Hdf5Writer& h5) {
  if (!gn.ok) {
    h5.attribute("/best", "gn_warning", gn.message);
    return;
  }
  const LeastSquaresUncertainty& u = gn.uncertainty;
  const auto q = static_cast<std::size_t>(u.covariance.rows());
  h5.write("/best/names_uncertainty", gn.names);
  h5.write("/best/covariance", row_major(u.covariance), q, q);
  h5.write("/best/correlation", row_major(u.correlation), q, q);
  h5.write("/best/stderr", std::vector<double>(u.standard_error.begin(), u.standard_error.end()));
  h5.write("/best/lower", std::vector<double>(u.lower.begin(), u.lower.end()));
  h5.write("/best/upper", std::vector<double>(u.upper.begin(), u.upper.end()));
  h5.write("/best/noise_sd", gn.noise_sd);
  h5.attribute("/best", "degrees_of_freedom", static_cast<long long>(u.degrees_of_freedom));
  h5.attribute("/best", "jacobian_rank", static_cast<long long>(u.rank));
  h5.attribute("/best", "gn_warning", u.warning);
}

void write_curves_and_profiles(const CalibrationFitResult& r, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {  // curve 0 at /data, /fit; curve k at /data/k, /fit/k
    const std::string suffix = k == 0 ? "" : "/" + std::to_string(k);
    h5.write("/data" + suffix + "/t", s.datasets[k].t);
    h5.write("/data" + suffix + "/z", s.datasets[k].z);
    h5.write("/fit" + suffix + "/t", r.fitted_curves[k].t_s);
    h5.write("/fit" + suffix + "/z", r.fitted_curves[k].z_m);
  }
  std::vector<std::string> channels;
  for (const CalibrationDataset& d : s.datasets) channels.push_back(d.channel + " of " + d.path);
  h5.write("/data/curves", channels);
  for (const ParameterProfile& prof : r.profiles) {
    const std::string g = "/profile/" + prof.name;
    h5.write(g + "/values", prof.values);
    h5.write(g + "/weighted_rss", prof.weighted_rss);
    if (!prof.complete) continue;
    h5.attribute(g, "best", prof.interval.best);
    h5.attribute(g, "lower", prof.interval.lower);
    h5.attribute(g, "upper", prof.interval.upper);
    h5.attribute(g, "identifiable", static_cast<long long>(prof.interval.identifiable));
  }
}

void report_intervals(const CalibrationFitResult& r, std::ostream& out) {
  const GaussNewtonResult& gn = r.checked.gn;
  const LeastSquaresUncertainty& u = gn.uncertainty;
  const std::size_t p = r.checked.fit.values.size();
  out << "calibrate: noise sd from the residuals";
  for (double sd : gn.noise_sd) out << " " << format_number(sd * 1000.0);
  out << " mm (" << u.degrees_of_freedom << " degrees of freedom); Gauss-Newton 95 % intervals"
      << (r.trusted ? "" : " (NOT VALID)") << ":\n";
  for (std::size_t k = 0; k < gn.names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double value = k < p ? r.checked.fit.values[k] : r.checked.fit.offsets[k - p];
    out << "  " << gn.names[k] << " = " << format_number(value, 6);
    if (std::isfinite(u.standard_error[i]))
      out << " +- " << format_number(u.upper[i] - value, 3) << " (95 %), se " << format_number(u.standard_error[i], 3);
    else
      out << ", no interval (not identifiable from these data)";
    out << (k >= p ? "  (profiled offset)" : "") << "\n";
  }
  out << "calibrate: correlation matrix (";
  for (std::size_t k = 0; k < gn.names.size(); ++k) out << (k ? ", " : "") << gn.names[k];
  out << "):\n";
  for (Eigen::Index i = 0; i < u.correlation.rows(); ++i) {
    out << " ";
    for (Eigen::Index j = 0; j < u.correlation.cols(); ++j) {
      char cell[32];
      if (std::isfinite(u.correlation(i, j))) std::snprintf(cell, sizeof cell, " %7.3f", u.correlation(i, j));
      else std::snprintf(cell, sizeof cell, " %7s", "none");
      out << cell;
    }
    out << "\n";
  }
  if (!u.warning.empty()) out << "calibrate: WARNING: " << u.warning << "\n";
}

void report_profiles(const CalibrationFitResult& r, std::ostream& out) {
  for (const ParameterProfile& prof : r.profiles) {
    out << "calibrate: profile of " << prof.name << ": ";
    if (!prof.complete) {
      out << "too few successful runs\n";
    } else if (!prof.interval.identifiable) {
      out << "NOT IDENTIFIABLE from these data (the profile stays below the 95 % threshold over ["
          << format_number(prof.values.front(), 6) << ", " << format_number(prof.values.back(), 6) << "])\n";
    } else {
      auto end = [](double v, bool open) { return open ? std::string(v < 0 ? "-inf" : "inf") + " (open)" : format_number(v, 6); };
      out << "best " << format_number(prof.interval.best, 6) << ", 95 % profile-likelihood interval ["
          << end(prof.interval.lower, prof.interval.lower_open) << ", "
          << end(prof.interval.upper, prof.interval.upper_open) << "]\n";
    }
  }
}

}  // namespace

void write_calibration_fit(const CalibrationFitResult& r, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  write_history(r, s, h5);
  write_best(r, s, h5);
  write_uncertainty(r.checked.gn, h5);
  write_curves_and_profiles(r, s, h5);
  h5.attribute("/", "data_file", s.data_path);
  h5.attribute("/", "method", std::string("optimize"));
  h5.attribute("/", "algorithm",
               s.algorithm == kLeastSquaresAlgorithm ? s.algorithm : s.algorithm + " then " + kLeastSquaresAlgorithm);
  h5.attribute("/", "max_evaluations", static_cast<long long>(s.max_evaluations));
  h5.attribute("/", "starts", static_cast<long long>(s.starts));
  h5.attribute("/", "calibration_fingerprint", io::key_summary(s.fingerprint));
}

void report_calibration_fit(const CalibrationFitResult& r, const CalibrationStudy& s, std::ostream& out) {
  const CheckedFit& c = r.checked;
  for (const std::string& action : c.integrator_actions) out << "calibrate: " << action << "\n";
  out << "calibrate: " << r.history.rows.size() / HistoryLayout(s).width() << " evaluations, " << c.fit.iterations
      << " least-squares iterations; " << (c.fit.converged ? "converged" : "NOT CONVERGED") << " (" << c.fit.message
      << ")\n";
  if (!r.trusted)
    out << "calibrate: WARNING: the intervals below are NOT VALID: " << r.not_valid_because
        << ". They are written flagged (/best intervals_valid = 0) and the exit status is 2.\n";
  out << "calibrate: best RMS " << format_residual_statistic(r.best_rms_m * 1000.0, 4, "mm") << " at";
  for (std::size_t k = 0; k < s.fit.size(); ++k) out << " " << s.fit[k].name << " = " << format_number(c.fit.values[k], 6);
  out << ", time offset" << (s.datasets.size() > 1 ? "s" : "");
  for (double o : c.fit.offsets) out << " " << format_number(o, 6);
  out << " s; residual lag-1 autocorrelation";
  for (double lag1 : r.curve_residual_lag1) out << " " << format_residual_statistic(lag1, 2);
  out << " (independent noise: near 0)\n";
  if (c.gn.ok) report_intervals(r, out);
  else out << "calibrate: WARNING: " << c.gn.message << "\n";
  report_profiles(r, out);
  if (!c.shift.ok) {
    if (!c.shift.message.empty()) out << "calibrate: integration check: " << c.shift.message << "\n";
    return;
  }
  out << "calibrate: integration check (" << describe_integrator(c.study.integrator) << " against "
      << describe_integrator(c.study.integration_check.reference) << "): shifts";
  for (std::size_t k = 0; k < s.fit.size(); ++k) out << " " << s.fit[k].name << " " << format_number(c.shift.shift_se[k], 2);
  out << " standard errors (limit " << format_number(c.study.integration_check.max_shift_se, 2) << ")\n";
}

}  // namespace rover::study
