// One simulation run by a one-process command (simulate, synthesize) that
// Ctrl-C or SIGTERM stops as they stop a study (docs/reliability.md, exit
// status 130): at the next step after the signal (the simulation reads the
// flag at every step), with a message and nothing written.
#pragma once

#include <string>

#include "core/simulate.hpp"

namespace rover::cli {

// simulate(model, scenario, inputs, observer); throws
// study::StudyInterrupted ("interrupted by SIGTERM at t = 2.1 of 168 s of
// the run; nothing written") when a SIGINT or SIGTERM arrives during the run.
// A second signal kills as usual.
Trajectory simulate_interruptibly(const RoverModel& model, const Scenario& scenario, const ModelInputs& inputs,
                                  const SimulationObserver& observer = {});

}  // namespace rover::cli
