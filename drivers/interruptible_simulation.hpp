// One simulation run by a one-process command (simulate, synthesize) that a
// signal (study::InterruptGuard: Ctrl-C, SIGTERM, SIGHUP, a closed output
// pipe) stops as it stops a study (docs/reliability.md, exit status 130): at
// the next step after the signal (the simulation reads the flag at every
// step), with a message and nothing written.
#pragma once

#include <string>

#include "core/simulate.hpp"

namespace rover::cli {

// simulate(model, scenario, inputs, observer); throws
// study::StudyInterrupted ("interrupted (SIGTERM) at t = 2.1 of the run's
// 168 s; nothing written") when such a signal arrives during the run.
// A second signal kills as usual.
Trajectory simulate_interruptibly(const RoverModel& model, const Scenario& scenario, const ModelInputs& inputs,
                                  const SimulationObserver& observer = {});

}  // namespace rover::cli
