// Rank 0's word to every rank of MPI_COMM_WORLD: a result computed on rank 0
// (the best point of a fit, the log densities of an ensemble half-step), so
// that all ranks take part in the next collective task farm with the same
// inputs; a verdict only rank 0 reaches (a refusal of the output path); and
// whether every rank was given rank 0's study. Without MPI initialised, or
// on one rank, each is a no-op.
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
