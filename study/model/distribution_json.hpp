// Probability distributions of study files: the {"distribution": ...} objects
// of "parameters", calibration priors and noise priors, read into
// study::Distribution (study/estimators/distributions.hpp).
#pragma once

#include "study/estimators/distributions.hpp"

namespace rover::io {
class JsonReader;
}

namespace rover::study {

// Parses {"distribution": "...", ...} (the other keys of the object are for
// the caller). `nominal` is the parameter's configured value (NaN if none).
// Keys:
//   fixed:        "value" (default: nominal)
//   uniform, log_uniform: "min", "max"
//   normal:       "mean" (default: nominal), and "sd" or "sd_percent"
//                 (sd = percent / 100 * |mean|), optional "truncate":
//                 [lower, upper] (null = infinite side)
//   lognormal:    "mean" and "sd" (or "sd_percent", the coefficient of
//                 variation in percent) of X itself (default mean: nominal),
//                 or "log_mean" and "log_sd"; optional "truncate" (null lower
//                 = 0)
// Every error goes through r.fail(key, ...) and so is an io::ConfigError
// naming the file, the field and the value. Does NOT call r.finish().
Distribution parse_distribution(const io::JsonReader& r, double nominal);

}  // namespace rover::study
