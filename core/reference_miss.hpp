// A reference curve that every compared curve misses by more than the span of
// the reference's own values (the RMS difference of docs/model.md §8): the
// sign of a reference in other units (millimetres typed as metres) or of
// another channel. One test and one sentence for every reader of a
// reference: `rover compare`, the surface study's RMS map and the rms_vs QoI.
#pragma once

#include <string>
#include <vector>

namespace rover {

// max - min of the finite values; 0 when there are none.
double value_span(const std::vector<double>& values);

// True when at least one of `rms` is finite and every finite one exceeds
// `span` (the reference's value_span).
bool every_rms_exceeds_span(const std::vector<double>& rms, double span);

// "<who> the reference <reference> by more than the <span> <unit> its values
// span: are they in SI units (metres, not millimetres), and of the <what>?"
// (`who` e.g. "every run misses"; `unit` may be empty; `what` e.g.
// "channel named".)
std::string reference_missed_text(const std::string& who, const std::string& reference, double span,
                                  const std::string& unit, const std::string& what);

}  // namespace rover
