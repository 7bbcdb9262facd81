// `rover surrogate`: trains a polynomial chaos or Gaussian-process surrogate
// of the QoIs on a design run now or on an existing result file, validates and
// saves it (--study); or evaluates a saved surrogate at the points of a design
// CSV (--predict). See study/studies/surrogate_study.hpp for the formats.
#include <chrono>
#include <iostream>

#include "drivers/command_registry.hpp"
#include "drivers/held_outputs.hpp"
#include "drivers/interruptible_outputs.hpp"
#include "drivers/launcher.hpp"
#include "drivers/study_options.hpp"
#include "io/csv.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/runtime/study_runner.hpp"
#include "io/hdf5_file.hpp"
#include "io/input_files.hpp"
#include "study/studies/surrogate_prediction.hpp"
#include "study/studies/surrogate_study.hpp"

namespace rover::cli {
namespace {

constexpr long long kMaxSurrogateSamples = 10'000'000;

struct SurrogateOptions {
  std::string study_path, predict_path, design_path, csv_path;
  std::optional<long long> samples;
  study::StudyRunOptions run;
};

study::StudyProgram<study::SurrogateStudyResult> load(const CLI::App& app, const SurrogateOptions& o) {
  FlagChecks checks;
  if (o.samples && (*o.samples < 1 || *o.samples > kMaxSurrogateSamples))
    checks.add("--samples must be from 1 to 1e7, got " + std::to_string(*o.samples));
  checks.throw_if_any();
  study::SurrogateStudy s = study::load_surrogate_study(o.study_path, {o.samples, std::nullopt});
  // Trained on a result file, the study runs nothing and keeps no checkpoint.
  if (!s.training_file.empty())
    for (const char* flag : {"--resume", "--checkpoint-every"})
      if (app.count(flag) > 0)
        checks.add(std::string(flag) + ": this study trains on the runs of " + s.training_file +
                   " and runs none itself, so it keeps no checkpoint: there is nothing to resume or flush; drop it");
  checks.throw_if_any();
  return study::surrogate_program(std::move(s));
}

// The files a saved surrogate was trained on, as its root attributes name
// them (relative to where it was trained): a prediction's --csv must not
// replace them either, though --predict does not read them.
io::InputFiles training_files(const std::string& model_path) {
  io::InputFiles files;
  const io::Hdf5Reader h5(model_path);
  for (const char* attribute : {"study_file", "scenario_file", "rover_file", "terrain_file"})
    if (h5.has_attribute("/", attribute))
      if (const std::string path = h5.attribute_string("/", attribute); !path.empty())
        files.add(path, "the attribute " + std::string(attribute) + " of --predict '" + model_path +
                            "' (the surrogate was trained on it)");
  return files;
}

// The flags of --study that a prediction has no use for: refused, not dropped.
constexpr const char* kStudyOnlyFlags[] = {"--samples", "--out", "--resume", "--restart", "--plots", "--no-plot",
                                           "--checkpoint-every", "--progress-interval"};

int predict(const CLI::App& app, const SurrogateOptions& o) {
  FlagChecks checks;
  for (const char* flag : kStudyOnlyFlags)
    if (app.count(flag) > 0)
      checks.add(std::string(flag) + " applies to --study, not to --predict (which writes only --csv, and no plot)");
  // One table to write: the other subcommands that run on one process are
  // refused under mpirun before they start (drivers/main.cpp).
  if (const int size = launcher_size(); size > 1)
    checks.add("--predict " + one_process_refusal(size) + " (--study shares its runs among processes)");
  if (o.design_path.empty() || o.csv_path.empty()) checks.add("--predict needs --design X.csv and --csv Y.csv");
  checks.output_file("--csv", o.csv_path);
  checks.distinct_files("--csv", o.csv_path, "--design", o.design_path);
  checks.distinct_files("--csv", o.csv_path, "--predict", o.predict_path);
  checks.throw_if_any();
  const study::SurrogateSet set = study::read_surrogate_set(o.predict_path);
  // The table's temporary <csv>.partial may not replace an input either.
  io::InputFiles inputs = training_files(o.predict_path);
  inputs.add(o.design_path, "--design");
  inputs.add(o.predict_path, "--predict");
  checks.not_an_input("--csv", o.csv_path, inputs, io::WrittenBeside::kTemporaries);
  checks.throw_if_any();
  checks.output_format("--csv", o.csv_path, "CSV", ".csv");  // after: an input it would destroy is named first
  checks.throw_if_any();
  const study::DesignMatrix x = study::surrogate_points(set, study::read_surrogate_design(set, o.design_path));
  if (o.run.dry_run) {
    std::cerr << "surrogate: dry run: " << x.rows() << " points of " << set.models.size() << " "
              << study::surrogate_kind_name(set.kind) << " model(s) checked, " << o.csv_path
              << " can be written; nothing was predicted or written\n";
    return 0;
  }
  // From here a signal ends the prediction or the writing with a word, and
  // nothing written (the lock and the temporary go as the exception unwinds).
  InterruptibleOutputs outputs({o.csv_path});
  const auto start = std::chrono::steady_clock::now();
  study::PredictionTable table;
  try {
    table = study::predict_surrogate_set(set, x, outputs.stop());
  } catch (const study::WorkStopped&) {
    outputs.interrupted_while("predicting");
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  HeldOutputs held;
  held.hold("--csv", o.csv_path);
  if (!io::write_csv(o.csv_path, table.header, table.columns, "", outputs.stop()))
    outputs.interrupted_while("writing " + o.csv_path);
  outputs.written(o.csv_path);
  std::cerr << "surrogate: " << x.rows() << " points of " << set.models.size() << " " << study::surrogate_kind_name(set.kind)
            << " model(s) in " << 1e6 * seconds / static_cast<double>(x.rows()) << " us per point; wrote "
            << o.csv_path << "\n";
  // Predictions of a model not to be trusted are written, and said to be so.
  int status = 0;
  for (const study::FittedSurrogate& model : set.models)
    if (const std::string distrust = study::surrogate_not_to_trust(model.output_name(), model.validation());
        !distrust.empty()) {
      std::cerr << "surrogate: WARNING: " << distrust << " (exit status 2)\n";
      status = study::kSomeQoiUnfittedStatus;
    }
  return status;
}

int run_surrogate_command(const CLI::App& app, const SurrogateOptions& o) {
  if (o.predict_path.empty() == o.study_path.empty())
    throw CommandLineError({"give --study S.json (train) or --predict model.h5 (evaluate a saved surrogate)"});
  if (!o.predict_path.empty()) return predict(app, o);
  std::vector<std::string> refused;
  for (const char* flag : {"--design", "--csv"})
    if (app.count(flag) > 0)
      refused.push_back(std::string(flag) + " applies to --predict, not to --study (a study's result goes to --out)");
  if (!refused.empty()) throw CommandLineError(refused);
  return run_study_command(app, o.run, o.study_path, [&] { return load(app, o); });
}

const RegisterCommand surrogate_command{
    57, "surrogate", "Polynomial chaos or kriging surrogate of the QoIs: train, validate and save it; or predict with it",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SurrogateOptions>();
      app.footer(std::string(
          "--study: one surrogate per QoI, a sparse polynomial chaos (\"surrogate\": \"pce\", LARS with the\n"
          "corrected leave-one-out error) or a Gaussian process (\"gp\", Matern 5/2), trained on the\n"
          "runs of the study's design (run now) or of an existing result file of montecarlo,\n"
          "evaluate, sensitivity or surrogate (\"training\": {\"file\": ...}); failed runs are left out\n"
          "and counted. Reports the leave-one-out Q2, a cross-validated Q2 that refits each fold from\n"
          "scratch (every PCE: terms re-selected; a GP on under 10 runs per input: length-scales\n"
          "re-estimated) and, with \"held_out\", the held-out Q2 and RMSE. Exits 2 when any of them is\n"
          "below q2_threshold (0.95 unless set: a model not to be trusted), and gives for a PCE the mean,\n"
          "variance and Sobol' indices with bootstrap intervals; \"channels\" (PCE) get S_i(t), mean\n"
          "and sd along time.\n"
          "Writes the model under /surrogate of --out and PNGs\n"
          "<out>_surrogate.png (surrogate against model) and <out>_surrogate_indices.png.\n"
          "--predict: the saved model at the rows of a design CSV (header of input names), mean and,\n"
          "for a GP, sd per QoI; a point outside the training support is refused. --dry-run checks\n"
          "the model, the design and --csv and writes nothing; the study's other flags are refused.\n\n"
          "Examples:\n"
          "  mpirun -np 2 rover surrogate --study configs/studies/surrogate_drop.json\n"
          "  rover surrogate --study configs/studies/surrogate_f_cq_gp.json --out results/gp.h5\n"
          "  rover surrogate --predict results/surrogate_drop.h5 --design X.csv --csv Y.csv\n\n") +
          kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type surrogate)")
          ->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples, "Override the number of runs of the study's design");
      app.add_option("--predict", o->predict_path, "A surrogate saved by --study (its --out file)")
          ->check(CLI::ExistingFile);
      app.add_option("--design", o->design_path, "With --predict: CSV of points, a header of input names")
          ->check(CLI::ExistingFile);
      app.add_option("--csv", o->csv_path, "With --predict: CSV of the predictions");
      add_study_flags(app, o->run);
      return [o, &app] { return run_surrogate_command(app, *o); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
