// A test model with a constant QoI, for the sensitivity studies' handling of
// QoIs whose indices are undefined: y = x1 + 2 x2^2 varies, c = 3 is
// constant, n = x1 is NaN where x1 > 0.8 (in runs that succeed).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "study/model/study_model.hpp"

namespace rover::study {

class ConstantQoiModel final : public StudyModel {
 public:
  // `inputs` >= 2 inputs x1, x2, ...; those beyond x2 do not enter any QoI.
  explicit ConstantQoiModel(int inputs = 2) {
    for (int i = 1; i <= inputs; ++i) inputs_.push_back("x" + std::to_string(i));
  }
  RunRecord run(const double* x) const override {
    RunRecord r;
    r.qoi = {x[0] + 2.0 * x[1] * x[1], 3.0, x[0] > 0.8 ? std::nan("") : x[0]};
    return r;
  }
  const std::vector<std::string>& input_names() const override { return inputs_; }
  const std::vector<std::string>& qoi_names() const override { return qois_; }
  const std::vector<std::string>& qoi_units() const override { return units_; }
  const std::vector<std::string>& channel_names() const override { return none_; }
  const std::vector<double>& time_s() const override { return no_times_; }
  std::string describe() const override { return "constant-qoi test model"; }

 private:
  std::vector<std::string> inputs_, qois_{"y", "c", "n"}, units_{"1", "1", "1"}, none_;
  std::vector<double> no_times_;
};

}  // namespace rover::study
