// See lars.hpp.
#include "study/surrogate/lars.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "study/estimators/work_stopped.hpp"
#include "study/surrogate/least_squares_loo.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Columns whose centred norm is below this (relative to the largest) are
// constant on the design and never enter.
constexpr double kNegligibleColumnNorm = 1e-12;
// The path stops when the largest correlation falls to this fraction of the first.
constexpr double kNegligibleCorrelation = 1e-12;
// An entering unit column whose squared distance to the span of the active
// ones is below this is collinear with them: the path ends there.
constexpr double kMinGramPivot = 1e-12;
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
  c_ = c0;
  Eigen::Index first = 0;
  c_max_ = c0.cwiseAbs().maxCoeff(&first);
  entering_ = static_cast<int>(first);
  ended_ = !(c_max_ > 0.0);
}

int LarsPath::next() {
  if (ended_ || entering_ < 0) return -1;
  const int column = entering_;
  usable_[column] = false;
  if (!extend_gram(column)) {  // in the span of the active columns: the path ends
    ended_ = true;
    return -1;
  }
  active_.push_back(column);
  // Prepare the following entry now; the path ends if there is none.
  const double c_now = c_.cwiseAbs().maxCoeff();
  if (c_now <= kNegligibleCorrelation * c_max_ || !step()) ended_ = true;
  return column + 1;
}

// Appends x_.col(column) to xa_ and a row to the Cholesky factor of
// xa_^T xa_: l = L^-1 xa_^T x, pivot sqrt(|x|^2 - |l|^2) with |x| = 1.
bool LarsPath::extend_gram(int column) {
  const Eigen::Index k = xa_.cols();
  const Eigen::VectorXd x = x_.col(column);
  const Eigen::VectorXd l = k == 0 ? Eigen::VectorXd()
                                   : Eigen::VectorXd(gram_l_.triangularView<Eigen::Lower>().solve(
                                         xa_.transpose() * x));
  const double pivot2 = 1.0 - l.squaredNorm();
  if (!(pivot2 > kMinGramPivot)) return false;
  xa_.conservativeResize(x_.rows(), k + 1);
  xa_.col(k) = x;
  gram_l_.conservativeResize(k + 1, k + 1);
  gram_l_.col(k).setZero();
  gram_l_.row(k).head(k) = l.transpose();
  gram_l_(k, k) = std::sqrt(pivot2);
  return true;
}

// The equiangular step (Efron et al. 2004, eqs. 2.4-2.13): moves mu along the
// direction equally correlated with the active columns until an inactive
// column is as correlated; that column is entering_. With s the signs of the
// active correlations and G the active Gram matrix, the signed system
// (S G S) w = 1 is solved as w = S G^-1 s. False if no column is left.
bool LarsPath::step() {
  const Eigen::VectorXd& c = c_;
  const Eigen::Index k = static_cast<Eigen::Index>(active_.size());
  Eigen::VectorXd signs(k);
  double big_c = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double cj = c(active_[static_cast<std::size_t>(j)]);
    signs(j) = cj >= 0.0 ? 1.0 : -1.0;
    big_c = std::max(big_c, std::abs(cj));
  }
  const Eigen::VectorXd half = gram_l_.triangularView<Eigen::Lower>().solve(signs);
  const Eigen::VectorXd g_inv_s = gram_l_.transpose().triangularView<Eigen::Upper>().solve(half);  // G^-1 s
  const double ones_w = signs.dot(g_inv_s);
  if (!(ones_w > 0.0)) return false;
  const double big_a = 1.0 / std::sqrt(ones_w);
  const Eigen::VectorXd u = xa_ * (big_a * g_inv_s);
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
  c_ -= gamma * a;  // = x_^T (yc_ - mu_)
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

namespace {

// Follows the path to its next column that is not in the span of the columns
// already in ls, and appends it there; -1 when the path ends or ls is full.
int append_next_column(LarsPath* path, const Eigen::MatrixXd& psi, int max_columns,
                       IncrementalLeastSquares* ls) {
  while (ls->columns() < max_columns) {
    const int column = path->next();
    if (column < 0) return -1;
    if (ls->add_column(psi.col(column))) return column;
  }
  return -1;
}

}  // namespace

SparseSelection hybrid_lars(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                            double y_variance, const std::atomic<bool>* stop) {
  SparseSelection best;
  best.corrected_loo = kInf;
  const int max_columns = static_cast<int>(std::min<Eigen::Index>(psi.cols(), psi.rows() - 1));
  LarsPath path(psi, y);
  IncrementalLeastSquares ls(y, y_variance);
  std::vector<int> columns;
  if (ls.add_column(psi.col(0))) columns.push_back(0);
  int since_best = 0;
  for (int step = 0;; ++step) {
    stop_if_requested(stop, "LARS basis selection");
    const LeastSquaresLoo fit = ls.fit();
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
    const int column = append_next_column(&path, psi, max_columns, &ls);
    if (column < 0) break;
    columns.push_back(column);
  }
  return best;
}

}  // namespace rover::study
