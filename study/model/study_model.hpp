// What a study evaluates: a pure, thread-safe function from a point of the
// input space to a RunRecord (quantities of interest and output curves). Every
// study (Monte Carlo, evaluate, response surfaces, sensitivity, calibration)
// runs its design through this one interface, so the analytic test models with
// known answers exercise exactly the code path of the rover.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario.hpp"
#include "io/scenario_config.hpp"
#include "study/model/parameter_space.hpp"
#include "study/model/qoi.hpp"
#include "study/runtime/run_record.hpp"

namespace rover::study {

class StudyModel {
 public:
  virtual ~StudyModel() = default;
  // Evaluates one point (input_count() values, in the order of input_names()).
  // Trouble becomes the record's status and message; the one exception is
  // WorkStopped, when a signal (InterruptGuard::flag()) ends the run midway:
  // it is not done, and the task farm hands it out again on --resume.
  virtual RunRecord run(const double* inputs) const = 0;
  virtual const std::vector<std::string>& input_names() const = 0;
  virtual const std::vector<std::string>& qoi_names() const = 0;
  virtual const std::vector<std::string>& qoi_units() const = 0;
  virtual const std::vector<std::string>& channel_names() const = 0;
  virtual const std::vector<double>& time_s() const = 0;  // the channels' time grid
  virtual std::string describe() const = 0;
  RecordLayout layout() const {
    return {static_cast<int>(qoi_names().size()), static_cast<int>(channel_names().size()),
            static_cast<int>(time_s().size())};
  }
  std::size_t input_count() const { return input_names().size(); }
};

// The rover on a scenario. Each run applies its input values to copies of the
// scenario's and rover's JSON (ParameterSpace), builds the scenario from them
// (the config files' validation: a value outside a parameter's valid range is a
// kRejectedInput record naming the field), simulates and computes the QoIs and
// channels. Friction gammas are synthesised once per distinct
// (mu_s, v_s, mu_k, v_k) and process (a mutex-guarded memo of a deterministic
// function: thread-safe and invisible in the results).
class RoverStudyModel final : public StudyModel {
 public:
  // `input_names`: canonical names (ParameterSpace::canonical). `integrator`
  // replaces the scenario's settings when given.
  RoverStudyModel(io::ScenarioSources sources, std::vector<std::string> input_names,
                  std::vector<QoiSpec> qois, std::vector<Channel> channels,
                  std::optional<IntegratorSettings> integrator = std::nullopt);

  RunRecord run(const double* inputs) const override;
  // The setup a point builds (throws io::ConfigError for a rejected point).
  io::ScenarioSetup setup_at(const double* inputs) const;
  // The trajectory of a point, or a failed record (status, message) in
  // `failure`; throws WorkStopped when a signal ends the run midway. `note` (if given) receives what to say of the point's setup:
  // friction gammas that miss their fit quality bar (mu_k above mu_s, say).
  std::optional<Trajectory> simulate_at(const double* inputs, RunRecord* failure, std::string* note = nullptr) const;

  const std::vector<std::string>& input_names() const override { return input_names_; }
  const std::vector<std::string>& qoi_names() const override { return qoi_names_; }
  const std::vector<std::string>& qoi_units() const override { return qoi_units_; }
  const std::vector<std::string>& channel_names() const override { return channel_names_; }
  const std::vector<double>& time_s() const override { return time_s_; }
  std::string describe() const override;

  const io::ScenarioSources& sources() const { return sources_; }
  const io::ScenarioSetup& nominal() const { return nominal_; }
  const std::vector<QoiSpec>& qois() const { return qois_; }
  const ParameterSpace& parameter_space() const { return *space_; }

 private:
  io::ScenarioSources sources_;
  std::unique_ptr<ParameterSpace> space_;
  std::vector<std::string> input_names_, qoi_names_, qoi_units_, channel_names_;
  std::vector<QoiSpec> qois_;
  std::vector<Channel> channels_;
  std::optional<IntegratorSettings> integrator_;
  std::vector<double> time_s_;
  io::ScenarioSetup nominal_;
  bool varies_friction_ = false;
  mutable std::mutex friction_mutex_;
  mutable std::map<std::array<double, 4>, std::array<double, 6>> friction_memo_;
};

// Analytic test models with known sensitivity indices (study/estimators/test_models.hpp):
// "ishigami" (a = 7, b = 0.1, d = 3), "sobol_g" (a = 0, 1, 4.5, 9, 99, 99, 99, 99),
// "linear" (y = sum_i a_i x_i, a_i = i). Inputs x1 .. xd, one QoI "y", no channels.
class AnalyticStudyModel final : public StudyModel {
 public:
  explicit AnalyticStudyModel(const std::string& name);
  RunRecord run(const double* inputs) const override;
  const std::vector<std::string>& input_names() const override { return input_names_; }
  const std::vector<std::string>& qoi_names() const override { return qoi_names_; }
  const std::vector<std::string>& qoi_units() const override { return qoi_units_; }
  const std::vector<std::string>& channel_names() const override { return no_channels_; }
  const std::vector<double>& time_s() const override { return no_times_; }
  std::string describe() const override { return name_; }
  const std::string& name() const { return name_; }
  static const std::vector<std::string>& model_names();
  // The coefficients: Ishigami (a, b), g-function a_i, linear a_i.
  const std::vector<double>& coefficients() const { return coefficients_; }

 private:
  std::string name_;
  std::vector<double> coefficients_;
  std::vector<std::string> input_names_, qoi_names_{"y"}, qoi_units_{"1"}, no_channels_;
  std::vector<double> no_times_;
};

}  // namespace rover::study
