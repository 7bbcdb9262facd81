// `rover surface`: RMS error and computation time over (f, c_q), and the
// sweep of t_c over f with its regression (paper Fig. 13a-c).
#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/studies/surface.hpp"

namespace rover::cli {
namespace {

struct SurfaceOptions {
  std::string study_path, integrator;
  study::StudyRunOptions run;
};

study::StudyProgram<study::SurfaceResult> load(const SurfaceOptions& o) {
  FlagChecks checks;
  check_integrator_flag(checks, o.integrator);
  checks.throw_if_any();
  study::SurfaceStudy s = study::load_surface_study(o.study_path);
  if (!o.integrator.empty()) s.integrator = default_integrator_settings(integrator_from_name(o.integrator));
  // The integrator in force is a setting of the runs' key, wherever it came from.
  s.fingerprint = study::with_setting(
      s.fingerprint, "--integrator",
      o.integrator.empty() ? "integrator" : o.integrator, !o.integrator.empty());
  return study::surface_program(std::move(s));
}

const RegisterCommand surface_command{
    55, "surface", "Response surfaces of RMS error and computation time over (f, c_q) (Fig. 13a-c)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SurfaceOptions>();
      app.footer(std::string(
          "At each (f, c_q) grid point: RMS of B_l z against the reference curve, and the wall\n"
          "time t_c of the run; plus a sweep over f with the regression t_c = a + b f. Writes\n"
          "/f /c_q /rms /t_c /sweep/{f,t_c,regression} and the figure <out>_summary.png; --plots all\n"
          "adds <out>_rms.png, <out>_tc.png, <out>_sweep.png. The integrator that produced t_c is\n"
          "recorded. With \"surrogate\": \"gp\" the grid is kriged from \"runs\" Latin hypercube runs\n"
          "(/gp/<qoi>/{mean,sd,lower,upper}); \"check\": \"grid\" also runs the grid and reports the\n"
          "error and the share of points within 3 predictive sd.\n\n"
          "Examples:\n"
          "  rover surface --study configs/studies/f_cq_surface.json\n"
          "  rover surface --study configs/studies/f_cq_surface.json --integrator rk4 --out results/rk4.h5\n"
          "  rover surface --study configs/studies/surface_gp.json\n"
          "  mpirun -np 8 rover surface --study configs/studies/f_cq_surface.json\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type surface)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--integrator", o->integrator, "Override the study's integrator, with that method's default tolerances: " +
                         integrator_choices_text());
      add_study_flags(app, o->run);
      return [o, &app] { return run_study_command(app, o->run, o->study_path, [&] { return load(*o); }); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
