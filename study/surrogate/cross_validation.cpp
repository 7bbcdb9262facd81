// See cross_validation.hpp.
#include "study/surrogate/cross_validation.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace rover::study {

CrossValidation cross_validate(const DesignMatrix& x, const Eigen::VectorXd& y, int min_training_runs,
                               const FitAndPredict& fit_and_predict) {
  CrossValidation cv;
  const Eigen::Index runs = y.size();
  const int folds = static_cast<int>(std::min<Eigen::Index>(kCrossValidationFolds, runs));
  const Eigen::Index largest_fold = folds > 0 ? (runs + folds - 1) / folds : 0;
  if (folds < 2 || runs - largest_fold < min_training_runs) {
    cv.why_not = "a fold of " + std::to_string(runs) + " runs leaves " + std::to_string(runs - largest_fold) +
                 " to refit on, and the fit needs " + std::to_string(min_training_runs);
    return cv;
  }
  const double spread = (y.array() - y.mean()).square().sum();
  if (!(spread > 0.0)) {
    cv.why_not = "the " + std::to_string(runs) + " values are equal: no spread to explain";
    return cv;
  }
  Eigen::VectorXd predicted(runs);
  for (int f = 0; f < folds; ++f) {
    std::vector<Eigen::Index> train, test;
    for (Eigen::Index r = 0; r < runs; ++r) (r % folds == f ? test : train).push_back(r);
    Eigen::VectorXd fold_prediction;
    try {
      using Eigen::placeholders::all;
      fold_prediction = fit_and_predict(x(train, all), y(train), x(test, all));
    } catch (const std::invalid_argument& e) {
      cv.why_not = "fold " + std::to_string(f + 1) + " of " + std::to_string(folds) + ": " + e.what();
      return cv;
    }
    for (std::size_t k = 0; k < test.size(); ++k) predicted(test[k]) = fold_prediction(static_cast<Eigen::Index>(k));
  }
  if (!predicted.allFinite()) {
    cv.why_not = "a refitted model predicted a non-finite value";
    return cv;
  }
  cv.folds = folds;
  cv.q2 = 1.0 - (y - predicted).squaredNorm() / spread;
  return cv;
}

}  // namespace rover::study
