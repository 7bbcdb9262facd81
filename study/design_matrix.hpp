// The matrix type of a batch of parameter points: one point per row, one
// parameter per column, rows contiguous so a point can be handed on (or sent
// to an MPI rank) as one block of doubles.
#pragma once

#include <Eigen/Core>

namespace rover::study {

using DesignMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace rover::study
