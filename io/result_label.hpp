// Names the user gives to results inside a study. A QoI's "label" becomes an
// HDF5 dataset path (/qoi/<label>), part of figure file names
// (<stem>_hist_<label>.png) and a CSV column name (`rover surrogate
// --predict`); a next-experiment candidate's "name" is shown in the ranking
// and saved as text. Both are checked before any run (docs/configuration.md).
#pragma once

#include <cstddef>
#include <string>

namespace rover::io {

inline constexpr std::size_t kMaxResultLabelLength = 64;
inline constexpr std::size_t kMaxDisplayNameLength = 200;

// "" if `label` is a plain name: 1 to kMaxResultLabelLength bytes, no '/',
// '\', ',' or '"', no "..", no control characters; else why not (quoting
// the label, control characters escaped).
std::string result_label_problem(const std::string& label);

// "" if `name` can be shown and saved as text: 1 to kMaxDisplayNameLength
// bytes, no control characters; else why not.
std::string display_name_problem(const std::string& name);

}  // namespace rover::io
