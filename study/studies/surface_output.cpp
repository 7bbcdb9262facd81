// The surface study's result file (surface.hpp; docs/results_format.md,
// "surface").
#include "study/studies/study_output.hpp"
#include "study/studies/surface.hpp"

namespace rover::study {

void write_surface(const SurfaceResult& r, io::Hdf5Writer& h5) {
  const SurfaceStudy& study = r.study;
  h5.write("/f", study.f);
  h5.write("/c_q", study.c_q);
  if (study.runs_grid()) {
    h5.write("/rms", r.rms);
    h5.write("/t_c", r.t_c);
    h5.write("/rhs_evaluations", r.rhs_evaluations);
    h5.write("/status", std::vector<double>(r.status.begin(), r.status.end()), study.f.size(), study.c_q.size());
    h5.write("/messages", r.messages);
  }
  if (study.kriging.enabled) write_surface_kriging(r.kriging, h5);
  h5.write("/reference/t", study.reference_t);
  h5.write("/reference/z", study.reference_z);
  if (!study.sweep_f.empty()) {
    h5.write("/sweep/f", study.sweep_f);
    h5.write("/sweep/t_c", r.sweep_t_c);
    h5.write("/sweep/rhs_evaluations", r.sweep_rhs_evaluations);
    h5.write("/sweep/regression", std::vector<double>{r.regression.intercept, r.regression.slope,
                                                      r.regression.r_squared});
    h5.attribute("/sweep", "c_q", study.sweep_c_q);
    h5.attribute("/sweep/regression", "meaning", "t_c = a + b f: [a (s), b (s), r^2]");
  }
  write_base_provenance(h5, "surface", study.name, study.path, &r.integrator, study.fingerprint);
  h5.attribute("/", "scenario", r.scenario_name);
  h5.attribute("/", "reference", study.reference_description);
  h5.attribute("/", "runs_key", study.runs_key);
  h5.attribute("/", "t_c_meaning", "wall time of one simulate() call on one core, seconds");
  h5.attribute("/", "failed_runs", static_cast<long long>(r.failed));
  if (!r.reference_warning.empty()) h5.attribute("/", "reference_warning", r.reference_warning);
}

}  // namespace rover::study
