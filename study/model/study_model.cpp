// See study_model.hpp.
#include "study/model/study_model.hpp"

#include <cmath>
#include <exception>

#include "core/friction_synthesis.hpp"
#include "core/number_text.hpp"
#include "core/run_note.hpp"
#include "study/estimators/test_models.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

const char* const kFrictionKeys[4] = {"mu_s", "v_s", "mu_k", "v_k"};


// Why a run's friction is not the law its parameters ask for, or empty: the
// Makkar gammas miss their fit quality bar (as `simulate` warns).
std::string friction_note(const FrictionParameters& friction) {
  const FrictionFitQuality fit = friction_fit_quality(friction.gammas, friction);
  if (fit.acceptable) return "";
  return run_note("the friction law misses its parameters",
                  "Makkar fit RMS " + number_text(fit.rms) + ", peak mu " + number_text(fit.peak_mu) +
                      " against mu_s " + number_text(friction.mu_static) +
                      " (mu_k above mu_s, or extreme Stribeck speeds? see `rover friction`)");
}

}  // namespace

RoverStudyModel::RoverStudyModel(io::ScenarioSources sources, std::vector<std::string> input_names,
                                 std::vector<QoiSpec> qois, std::vector<Channel> channels,
                                 std::optional<IntegratorSettings> integrator)
    : sources_(std::move(sources)),
      input_names_(std::move(input_names)),
      qois_(std::move(qois)),
      channels_(std::move(channels)),
      integrator_(integrator) {
  space_ = std::make_unique<ParameterSpace>(sources_.rover, sources_.scenario);
  for (const std::string& name : input_names_) {
    if (space_->canonical(name) != name)
      throw std::invalid_argument("input '" + name + "' is not a canonical parameter name");
    varies_friction_ = varies_friction_ || name.rfind("friction.", 0) == 0;
  }
  for (std::size_t j = 0; j < input_names_.size(); ++j)
    for (std::size_t k = 0; k < j; ++k)
      if (parameters_overlap(input_names_[k], input_names_[j]))
        throw std::invalid_argument("inputs '" + input_names_[k] + "' and '" + input_names_[j] +
                                    "' set a common number of the rover");
  for (const QoiSpec& q : qois_) {
    qoi_names_.push_back(q.name);
    qoi_units_.emplace_back(qoi_unit(q));
  }
  for (Channel c : channels_) channel_names_.emplace_back(channel_name(c));
  nominal_ = io::build_scenario(sources_);
  if (integrator_) nominal_.scenario.integrator = *integrator_;
  const std::size_t samples = output_sample_count(nominal_.scenario);
  time_s_.resize(samples);
  for (std::size_t k = 0; k < samples; ++k)
    time_s_[k] = static_cast<double>(k) / nominal_.scenario.output_rate_hz;
}

std::string RoverStudyModel::describe() const {
  return "scenario " + nominal_.scenario.name + " (" + sources_.scenario_path + ")";
}

io::ScenarioSetup RoverStudyModel::setup_at(const double* x) const {
  io::ScenarioSources run = sources_;
  for (std::size_t i = 0; i < input_names_.size(); ++i)
    space_->apply(input_names_[i], x[i], run.rover, run.scenario);
  if (varies_friction_) {
    // Pin the gammas of this (mu_s, v_s, mu_k, v_k) so the loader does not
    // synthesise them again for every run.
    io::Json& friction = run.rover["friction"];
    std::array<double, 4> key{};
    for (int k = 0; k < 4; ++k) key[k] = friction.value(kFrictionKeys[k], std::nan(""));
    std::array<double, 6> gammas{};
    bool known = false;
    {
      const std::lock_guard<std::mutex> lock(friction_mutex_);
      if (auto it = friction_memo_.find(key); it != friction_memo_.end()) {
        gammas = it->second;
        known = true;
      }
    }
    if (!known) {
      FrictionParameters p;
      p.mu_static = key[0];
      p.v_static_mps = key[1];
      p.mu_kinetic = key[2];
      p.v_kinetic_mps = key[3];
      try {
        gammas = synthesize_friction(p);
      } catch (const std::invalid_argument& e) {
        throw io::ConfigError(sources_.rover_path + ": friction (" + number_text(key[0]) + ", " +
                              number_text(key[1]) + ", " + number_text(key[2]) + ", " +
                              number_text(key[3]) + "): " + e.what());
      }
      const std::lock_guard<std::mutex> lock(friction_mutex_);
      friction_memo_.emplace(key, gammas);
    }
    friction["gammas"] = gammas;
    friction["gammas_fitted_to"] = key;
  }
  // A refused value is this run's, not the file's: messages say so.
  run.rover_path += " with this run's sampled values";
  io::ScenarioSetup setup = io::build_scenario(run);
  setup.rover_path = sources_.rover_path;
  if (integrator_) setup.scenario.integrator = *integrator_;
  return setup;
}

std::optional<Trajectory> RoverStudyModel::simulate_at(const double* x, RunRecord* failure, std::string* note) const {
  const RecordLayout shape = layout();
  try {
    const io::ScenarioSetup setup = setup_at(x);
    if (note != nullptr && varies_friction_) *note = friction_note(setup.model.parameters.friction);
    SimulationObserver observer;
    observer.stop = &InterruptGuard::flag();  // a signal ends the run at its next step
    Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs, observer);
    if (note != nullptr) *note = join_notes({*note, chassis_through_ground_note(tr, setup.model.terrain)});
    return tr;
  } catch (const SimulationStopped& e) {
    throw WorkStopped(e.what());  // not done: neither a result nor a failure
  } catch (const io::ConfigError& e) {
    *failure = failed_record(shape, run_status::kRejectedInput, e.what());
  } catch (const std::exception& e) {
    *failure = failed_record(shape, run_status::kError, e.what());
  }
  return std::nullopt;
}

namespace {

// The notes of a finished run, "; "-separated: its setup's (`setup_note`),
// no wheel touched the ground, and QoIs whose value is not what their name
// says (qoi_note).
std::string run_notes(const std::string& setup_note, const Trajectory& tr, const std::vector<QoiSpec>& qois) {
  std::vector<std::string> notes{setup_note, no_wheel_touched_note(tr)};
  for (const QoiSpec& q : qois) notes.push_back(qoi_note(q, tr));
  return join_notes(notes);
}

}  // namespace

RunRecord RoverStudyModel::run(const double* x) const {
  const RecordLayout shape = layout();
  RunRecord record;
  std::string setup_note;
  std::optional<Trajectory> tr = simulate_at(x, &record, &setup_note);
  if (!tr) return record;
  if (!tr->ok()) {
    record = failed_record(shape, static_cast<int>(tr->status), tr->message);
  } else {
    record.qoi.reserve(qois_.size());
    try {
      for (const QoiSpec& q : qois_) record.qoi.push_back(compute_qoi(q, *tr));
    } catch (const std::exception& e) {
      record = failed_record(shape, run_status::kError, std::string("computing the QoIs: ") + e.what());
    }
    if (record.ok()) record.message = run_notes(setup_note, *tr, qois_);
    const auto T = static_cast<std::size_t>(shape.time_samples);
    record.curves.assign(channels_.size() * T, std::nan(""));
    for (std::size_t c = 0; c < channels_.size() && record.ok(); ++c) {
      const std::vector<double> values = channel_values(*tr, channels_[c]);
      std::copy_n(values.begin(), std::min(values.size(), T), record.curves.begin() + static_cast<std::ptrdiff_t>(c * T));
    }
  }
  record.rhs_evaluations = static_cast<double>(tr->rhs_evaluations);
  record.wall_time_s = tr->wall_time_s;
  return record;
}

const std::vector<std::string>& AnalyticStudyModel::model_names() {
  static const std::vector<std::string> names{"ishigami", "sobol_g", "linear"};
  return names;
}

AnalyticStudyModel::AnalyticStudyModel(const std::string& name) : name_(name) {
  int d = 0;
  if (name == "ishigami") {
    coefficients_ = {7.0, 0.1};
    d = 3;
  } else if (name == "sobol_g") {
    coefficients_ = {0.0, 1.0, 4.5, 9.0, 99.0, 99.0, 99.0, 99.0};
    d = 8;
  } else if (name == "linear") {
    coefficients_ = {1.0, 2.0, 3.0, 4.0};
    d = 4;
  } else {
    std::string valid;
    for (const std::string& n : model_names()) valid += (valid.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown analytic model '" + name + "' (valid: " + valid + ")");
  }
  for (int i = 1; i <= d; ++i) input_names_.push_back(std::string(1, 'x').append(std::to_string(i)));
}

RunRecord AnalyticStudyModel::run(const double* x) const {
  RunRecord r;
  double y = std::nan("");
  if (name_ == "ishigami") y = ishigami(x, coefficients_[0], coefficients_[1]);
  if (name_ == "sobol_g") y = sobol_g(x, coefficients_);
  if (name_ == "linear") y = linear_model(x, coefficients_);
  if (!std::isfinite(y)) return failed_record(layout(), run_status::kError, "non-finite output");
  r.qoi = {y};
  return r;
}

}  // namespace rover::study
