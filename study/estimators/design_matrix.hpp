// The design matrix of a study: one run per row, one input per column, stored
// row by row so that a run's inputs are contiguous (`design.row(r).data()`).
#pragma once

#include <Eigen/Core>

namespace rover::study {

using DesignMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace rover::study
