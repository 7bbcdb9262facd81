// Notes on finished runs: a run that ends without error but whose values are
// not what their names say (no wheel touched the ground, a friction law that
// misses its parameters, an at_rest that is no rest height). A note reads
// "<kind>: <details>": the kind is the same words for every run with that
// problem, the details are the run's own numbers and advice. A run's notes
// are joined with "; " into its message (docs/results_format.md), and a
// study counts its runs per kind (study/studies/study_driver.hpp). The kind
// ends at the first ": " or " (", so that notes written as "<kind> (<details>)"
// are grouped by kind too.
#pragma once

#include <string>
#include <vector>

namespace rover {

inline constexpr const char* kNoteKindEnd = ": ";
inline constexpr const char* kNoteDetailsOpen = " (";
inline constexpr const char* kNoteSeparator = "; ";

// "<kind>: <details>". A separator inside a part (a QoI's label in a kind)
// is replaced so that the note reads back: "; " by ", " and, in the kind,
// ": " and " (" by " ".
std::string run_note(std::string kind, std::string details);

// The notes joined with "; ", empty ones left out.
std::string join_notes(const std::vector<std::string>& notes);

// A run's message split back into its notes.
std::vector<std::string> split_notes(const std::string& message);

// A note's kind: its words before the first ": " or " (" (the whole note if
// neither).
std::string note_kind(const std::string& note);

}  // namespace rover
