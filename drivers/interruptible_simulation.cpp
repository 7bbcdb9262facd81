// See interruptible_simulation.hpp.
#include "drivers/interruptible_simulation.hpp"

#include "core/number_text.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {
namespace {

[[noreturn]] void throw_interrupted(double t_s, double duration_s) {
  throw study::StudyInterrupted("interrupted (" + study::InterruptGuard::signal_name() + ") at t = " +
                                number_text(t_s) + " of the run's " + number_text(duration_s) +
                                " s; nothing written");
}

}  // namespace

Trajectory simulate_interruptibly(const RoverModel& model, const Scenario& scenario, const ModelInputs& inputs,
                                  const SimulationObserver& observer) {
  const study::InterruptGuard guard;
  SimulationObserver watched = observer;
  watched.stop = &study::InterruptGuard::flag();  // read at every step: the run ends at once
  try {
    Trajectory tr = simulate(model, scenario, inputs, watched);
    if (study::InterruptGuard::flag().load())
      throw_interrupted(tr.t.empty() ? 0.0 : tr.t.back(), scenario.duration_s);
    return tr;
  } catch (const SimulationStopped& e) {
    throw_interrupted(e.t_s, scenario.duration_s);
  }
}

}  // namespace rover::cli
