// Broadcast of a result computed on rank 0 (the best point of a fit, the log
// densities of an ensemble half-step) to every rank of MPI_COMM_WORLD, so that
// all ranks can take part in the next collective task farm with the same
// inputs. Without MPI initialised, or on one rank, a no-op.
#pragma once

#include <string>
#include <vector>

namespace rover::study {

// Collective: every rank calls it; afterwards every rank holds rank 0's
// `values` (resized as needed).
void broadcast_from_rank0(std::vector<double>& values);

// Collective: rank 0's `flag` on every rank (a verdict only rank 0 can reach,
// such as a refusal that every rank must act on).
bool broadcast_flag_from_rank0(bool flag);

// Collective: whether `text` differs from rank 0's on any rank (every rank
// gets the same answer).
bool differs_from_rank0_anywhere(const std::string& text);

}  // namespace rover::study
