// See fitted_surrogate.hpp.
#include "study/surrogate/fitted_surrogate.hpp"

#include <stdexcept>

#include <Eigen/QR>

#include "study/surrogate/pce_basis.hpp"

namespace rover::study {
namespace {

// A leverage this close to 1 leaves the run's own residual undetermined.
constexpr double kMaxLeverage = 1.0 - 1e-12;

}  // namespace

const char* surrogate_kind_name(SurrogateKind kind) {
  return kind == SurrogateKind::kPolynomialChaos ? "pce" : "gp";
}

SurrogateKind surrogate_kind_from_name(const std::string& name) {
  if (name == "pce") return SurrogateKind::kPolynomialChaos;
  if (name == "gp") return SurrogateKind::kGaussianProcess;
  throw std::invalid_argument("unknown surrogate '" + name + "': expected \"pce\" (polynomial chaos) or \"gp\" (kriging)");
}

const std::string& FittedSurrogate::output_name() const {
  return kind == SurrogateKind::kPolynomialChaos ? pce.output_name : gp.output_name;
}

const SurrogateValidation& FittedSurrogate::validation() const {
  return kind == SurrogateKind::kPolynomialChaos ? pce.validation : gp.validation;
}

SurrogateValidation& FittedSurrogate::validation() {
  return kind == SurrogateKind::kPolynomialChaos ? pce.validation : gp.validation;
}

int FittedSurrogate::runs() const { return kind == SurrogateKind::kPolynomialChaos ? pce.runs : gp.runs; }

DesignMatrix to_unit_cube(const DesignMatrix& x, const std::vector<Distribution>& inputs) {
  if (x.cols() != static_cast<Eigen::Index>(inputs.size()))
    throw std::invalid_argument("surrogate: points have " + std::to_string(x.cols()) + " columns for " +
                                std::to_string(inputs.size()) + " inputs");
  DesignMatrix u(x.rows(), x.cols());
  for (Eigen::Index j = 0; j < x.cols(); ++j)
    for (Eigen::Index i = 0; i < x.rows(); ++i) u(i, j) = inputs[static_cast<std::size_t>(j)].cdf(x(i, j));
  return u;
}

FittedSurrogate polynomial_chaos_surrogate(PolynomialChaosExpansion expansion) {
  FittedSurrogate s;
  s.kind = SurrogateKind::kPolynomialChaos;
  s.inputs = expansion.inputs;
  s.pce = std::move(expansion);
  return s;
}

FittedSurrogate fit_gaussian_process_surrogate(const DesignMatrix& x, const Eigen::VectorXd& y,
                                               const std::vector<Distribution>& inputs,
                                               const GaussianProcessSettings& settings,
                                               const std::string& output_name) {
  FittedSurrogate s;
  s.kind = SurrogateKind::kGaussianProcess;
  s.inputs = inputs;
  s.gp = fit_gaussian_process(to_unit_cube(x, inputs), y, settings, output_name);
  return s;
}

SurrogatePrediction predict_surrogate(const FittedSurrogate& s, const DesignMatrix& x) {
  SurrogatePrediction out;
  if (s.kind == SurrogateKind::kPolynomialChaos) {
    out.mean = s.pce.evaluate(x);
    out.sd = Eigen::VectorXd::Zero(x.rows());
    return out;
  }
  GaussianProcessPrediction p = predict_gaussian_process(s.gp, to_unit_cube(x, s.inputs));
  out.mean = std::move(p.mean);
  out.sd = p.variance.cwiseSqrt();
  return out;
}

void validate_surrogate(const DesignMatrix& x_test, const Eigen::VectorXd& y_test, double q2_threshold,
                        FittedSurrogate* s) {
  if (s->kind == SurrogateKind::kPolynomialChaos)
    validate_polynomial_chaos(x_test, y_test, q2_threshold, &s->pce);
  else
    validate_gaussian_process(to_unit_cube(x_test, s->inputs), y_test, q2_threshold, &s->gp);
}

Eigen::VectorXd leave_one_out_predictions(const FittedSurrogate& s, const DesignMatrix& x,
                                          const Eigen::VectorXd& y) {
  if (s.kind == SurrogateKind::kGaussianProcess) return s.gp.loo_mean;
  const Eigen::MatrixXd psi = pce_basis_matrix(x, s.pce.inputs, s.pce.multi_indices);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(psi);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(psi.rows(), psi.cols());
  const Eigen::VectorXd leverage = q.rowwise().squaredNorm();
  const Eigen::VectorXd fitted = psi * s.pce.coefficients;
  Eigen::VectorXd loo = fitted;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (leverage(i) < kMaxLeverage) loo(i) = y(i) - (y(i) - fitted(i)) / (1.0 - leverage(i));
  return loo;
}

}  // namespace rover::study
