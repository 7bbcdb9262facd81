// See lars.hpp.
#include "study/surrogate/lars.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "study/surrogate/least_squares_loo.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Columns whose centred norm is below this (relative to the largest) are
// constant on the design and never enter.
constexpr double kNegligibleColumnNorm = 1e-12;
// The path stops when the largest correlation falls to this fraction of the first.
constexpr double kNegligibleCorrelation = 1e-12;
// Hybrid LARS stops once the corrected LOO error has not improved for this
// many steps, or this fraction of the steps taken, whichever is larger.
constexpr int kMinPatienceSteps = 20;
constexpr double kPatienceFraction = 0.5;

}  // namespace

LarsPath::LarsPath(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y) {
  const Eigen::Index candidates = psi.cols() - 1;
  yc_ = y.array() - y.mean();
  mu_ = Eigen::VectorXd::Zero(y.size());
  if (candidates < 1) {
    ended_ = true;
    return;
  }
  x_ = psi.rightCols(candidates).rowwise() - psi.rightCols(candidates).colwise().mean();
  const Eigen::VectorXd norms = x_.colwise().norm().transpose();
  const double largest = norms.maxCoeff();
  usable_.assign(static_cast<std::size_t>(candidates), false);
  Eigen::VectorXd c0 = Eigen::VectorXd::Zero(candidates);
  for (Eigen::Index j = 0; j < candidates; ++j)
    if (norms(j) > kNegligibleColumnNorm * largest) {
      x_.col(j) /= norms(j);
      usable_[j] = true;
      c0(j) = x_.col(j).dot(yc_);
    }
  Eigen::Index first = 0;
  c_max_ = c0.cwiseAbs().maxCoeff(&first);
  entering_ = static_cast<int>(first);
  ended_ = !(c_max_ > 0.0);
}

int LarsPath::next() {
  if (ended_ || entering_ < 0) return -1;
  const int column = entering_;
  active_.push_back(column);
  usable_[column] = false;
  // Prepare the following entry now; the path ends if there is none.
  const double c_now = (x_.transpose() * (yc_ - mu_)).cwiseAbs().maxCoeff();
  if (c_now <= kNegligibleCorrelation * c_max_ || !step()) ended_ = true;
  return column + 1;
}

// The equiangular step (Efron et al. 2004, eqs. 2.4-2.13): moves mu along the
// direction equally correlated with the active columns until an inactive
// column is as correlated; that column is entering_. False if the active Gram
// matrix is singular or no column is left.
bool LarsPath::step() {
  const Eigen::VectorXd c = x_.transpose() * (yc_ - mu_);
  const Eigen::Index k = static_cast<Eigen::Index>(active_.size());
  Eigen::MatrixXd xa(x_.rows(), k);
  double big_c = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const int col = active_[static_cast<std::size_t>(j)];
    xa.col(j) = (c(col) >= 0.0 ? 1.0 : -1.0) * x_.col(col);
    big_c = std::max(big_c, std::abs(c(col)));
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(xa.transpose() * xa);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::VectorXd w0 = llt.solve(Eigen::VectorXd::Ones(k));
  const double ones_w = w0.sum();
  if (!(ones_w > 0.0)) return false;
  const double big_a = 1.0 / std::sqrt(ones_w);
  const Eigen::VectorXd u = xa * (big_a * w0);
  const Eigen::VectorXd a = x_.transpose() * u;
  double gamma = big_c / big_a;
  entering_ = -1;
  for (Eigen::Index j = 0; j < x_.cols(); ++j) {
    if (!usable_[static_cast<std::size_t>(j)]) continue;
    for (const double g : {(big_c - c(j)) / (big_a - a(j)), (big_c + c(j)) / (big_a + a(j))})
      if (g > 0.0 && g < gamma) {
        gamma = g;
        entering_ = static_cast<int>(j);
      }
  }
  mu_ += gamma * u;
  return entering_ >= 0;
}

std::vector<int> lars_entry_order(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                  int max_steps) {
  std::vector<int> order;
  LarsPath path(psi, y);
  for (int column = 0; static_cast<int>(order.size()) < max_steps && (column = path.next()) > 0;)
    order.push_back(column);
  return order;
}

SparseSelection hybrid_lars(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                            double y_variance) {
  SparseSelection best;
  best.corrected_loo = kInf;
  const Eigen::Index max_columns = std::min<Eigen::Index>(psi.cols(), psi.rows() - 1);
  LarsPath path(psi, y);
  std::vector<int> columns{0};
  Eigen::MatrixXd sub = psi.leftCols(1);
  int since_best = 0;
  for (int step = 0;; ++step) {
    const LeastSquaresLoo fit = least_squares_loo(sub, y, y_variance);
    if (fit.ok && fit.corrected_loo < best.corrected_loo) {
      best.ok = true;
      best.columns = columns;
      best.coefficients = fit.coefficients;
      best.corrected_loo = fit.corrected_loo;
      since_best = 0;
    } else if (++since_best >= std::max<int>(kMinPatienceSteps,
                                            static_cast<int>(kPatienceFraction * step))) {
      break;
    }
    if (static_cast<Eigen::Index>(columns.size()) >= max_columns) break;
    const int column = path.next();
    if (column < 0) break;
    columns.push_back(column);
    sub.conservativeResize(Eigen::NoChange, sub.cols() + 1);
    sub.col(sub.cols() - 1) = psi.col(column);
  }
  return best;
}

}  // namespace rover::study
