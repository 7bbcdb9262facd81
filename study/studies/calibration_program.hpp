// The calibration studies as programs of the study driver
// (study/studies/study_driver.hpp): the fit with its intervals, and the
// posterior that starts from it. The driver owns the results path, the
// checkpoint, interrupts and the exit status; a result whose intervals cannot
// be trusted (a fit not converged or flagged, chains that did not mix) asks
// for kUntrustedStatus. Method: docs/studies.md, "Calibrate your own drop data".
#pragma once

#include <ostream>

#include "io/hdf5_file.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/calibration_checked_fit.hpp"
#include "study/studies/calibration_mcmc.hpp"
#include "study/studies/study_driver.hpp"

namespace rover::study {

// The exit status of a calibration whose intervals cannot be trusted.
inline constexpr int kUntrustedStatus = 2;

// A posterior run: the chains, and the study with the integrator the fit's
// integration check chose for them.
struct CalibrationPosteriorResult {
  CalibrationStudy study;
  bool started_at_initial_values = false;  // the fit had no intervals to start from
  std::string start_fit_flaw;               // why the fit started from is not to be trusted (rank 0)
  CalibrationPosterior posterior;
  // When every run of the fit failed, no chain starts: why (rank 0), and the
  // fit's runs, which the study then reports as failed (exit status 2).
  std::string not_sampled_because;
  RunCounts fit_counts;
};

// Collective: the checked fit, then the chains from it.
CalibrationPosteriorResult run_calibration_posterior(const CalibrationStudy& study, const StudyRunOptions& control);
// Where the chains started, then report_calibration_posterior.
void report_calibration_posterior_run(const CalibrationPosteriorResult& result, std::ostream& out);

// The root attributes of a calibration result (write_base_provenance, with
// the integrator the study starts on).
void write_calibration_provenance(io::Hdf5Writer& h5, const CalibrationStudy& study);

StudyProgram<CalibrationFitResult> calibration_fit_program(CalibrationStudy study);
StudyProgram<CalibrationPosteriorResult> calibration_posterior_program(CalibrationStudy study);

}  // namespace rover::study
