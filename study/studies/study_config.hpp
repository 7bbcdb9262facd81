// The run options with an on/off plot switch, used by `rover surrogate`
// until it moves to the study driver (study_driver.hpp).
#pragma once

#include "study/runtime/study_runner.hpp"

namespace rover::study {

struct StudyRunControl : StudyRunOptions {
  bool plot = true;
};

}  // namespace rover::study
