// `rover surface`: RMS error and computation time over (f, c_q), and the
// sweep of t_c over f with its regression (paper Fig. 13a-c).
#include <iostream>

#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "drivers/study_options.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/surface.hpp"

namespace rover::cli {
namespace {

struct SurfaceOptions {
  std::string study_path, integrator;
  study::StudyRunControl control;
};

int run_surface_command(SurfaceOptions& o) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  check_integrator_flag(checks, o.integrator);
  check_study_output(checks, o.control, o.study_path);
  checks.throw_if_any();
  study::SurfaceStudy s = study::load_surface_study(o.study_path);
  if (!o.integrator.empty()) {
    s.integrator = default_integrator_settings(integrator_from_name(o.integrator));
    s.fingerprint = study::extend_fingerprint(s.fingerprint, "integrator " + o.integrator);
  }
  o.control.resume_command = "rover surface --study " + o.study_path +
                             (o.integrator.empty() ? "" : " --integrator " + o.integrator) +
                             (o.control.results_path.empty() ? "" : " --out " + o.control.results_path) + " --resume";
  if (mpi.rank() == 0)
    std::cerr << "surface: " << s.f.size() << " x " << s.c_q.size() << " grid + " << s.sweep_f.size()
              << " sweep runs of " << s.sources.scenario_path << " on " << mpi.size() << " rank(s)\n";
  const study::InterruptGuard interrupts;
  return run_interruptible("surface", [&] {
    study::run_surface(s, o.control);
    return 0;
  });
}

const RegisterCommand registration{
    55, "surface", "Response surfaces of RMS error and computation time over (f, c_q) (Fig. 13a-c)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SurfaceOptions>();
      app.footer(std::string(
          "At each (f, c_q) grid point: RMS of B_l z against the reference curve, and the wall\n"
          "time t_c of the run; plus a sweep over f with the regression t_c = a + b f. Writes\n"
          "/f /c_q /rms /t_c /sweep/{f,t_c,regression} and PNGs <out>_rms.png, <out>_tc.png,\n"
          "<out>_sweep.png. The integrator that produced t_c is recorded.\n\n"
          "Examples:\n"
          "  rover surface --study configs/studies/f_cq_surface.json\n"
          "  rover surface --study configs/studies/f_cq_surface.json --integrator rk4 --out results/rk4.h5\n"
          "  mpirun -np 8 rover surface --study configs/studies/f_cq_surface.json\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type surface)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--integrator", o->integrator, "Override the study's integrator, with that method's default tolerances: " +
                         integrator_choices_text());
      add_study_control(app, o->control);
      return [o] { return run_surface_command(*o); };
    }};

}  // namespace
}  // namespace rover::cli
