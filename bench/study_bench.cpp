// The study machinery's cost per run against the run itself (study/): for one
// Monte Carlo sample of the preload study on the horizontal drop with the
// stiff integrator, the pieces a study adds around simulate():
//   setup      applying the sample's values to the config JSON and building
//              the scenario and model from it (validation included);
//   qoi        the seven QoIs and the B_l_z channel from the trajectory;
//   record     encoding the run record for MPI / the checkpoint and decoding it;
//   band       adding one curve to the streaming band (T = 1001);
// and the run itself (RoverStudyModel::run, which includes setup and qoi).
//
// Run on one quiet core: `taskset -c 0 build/bench/study_bench`.
#include <benchmark/benchmark.h>

#include "study/studies/montecarlo.hpp"
#include "study/estimators/streaming_band.hpp"

namespace {

using namespace rover;
using namespace rover::study;

const MonteCarloStudy& preload_study() {
  static const MonteCarloStudy study = load_montecarlo_study(ROVER_SOURCE_DIR "/configs/studies/preload_mc.json");
  return study;
}

const DesignMatrix& design() {
  static const DesignMatrix x = [] {
    MonteCarloStudy s = preload_study();
    s.spec.design.samples = 16;
    return study_design(s.spec);
  }();
  return x;
}

void BM_Setup(benchmark::State& state) {
  const RoverStudyModel& model = *preload_study().spec.rover;
  Eigen::Index i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.setup_at(design().row(i).data()));
    i = (i + 1) % design().rows();
  }
}
BENCHMARK(BM_Setup)->Unit(benchmark::kMicrosecond);

void BM_Run(benchmark::State& state) {
  const RoverStudyModel& model = *preload_study().spec.rover;
  Eigen::Index i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.run(design().row(i).data()));
    i = (i + 1) % design().rows();
  }
}
BENCHMARK(BM_Run)->Unit(benchmark::kMillisecond);

void BM_QoisAndChannel(benchmark::State& state) {
  const RoverStudyModel& model = *preload_study().spec.rover;
  RunRecord failure;
  const Trajectory tr = *model.simulate_at(design().row(0).data(), &failure);
  for (auto _ : state) {
    double sum = 0.0;
    for (const QoiSpec& q : model.qois()) sum += compute_qoi(q, tr);
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(channel_values(tr, Channel::kBlz));
  }
}
BENCHMARK(BM_QoisAndChannel)->Unit(benchmark::kMicrosecond);

void BM_RecordRoundTrip(benchmark::State& state) {
  const RoverStudyModel& model = *preload_study().spec.rover;
  const RunRecord record = model.run(design().row(0).data());
  for (auto _ : state) benchmark::DoNotOptimize(decode_record(model.layout(), encode_record(0, record)));
}
BENCHMARK(BM_RecordRoundTrip)->Unit(benchmark::kMicrosecond);

void BM_StreamingBandAdd(benchmark::State& state) {
  const RoverStudyModel& model = *preload_study().spec.rover;
  const RunRecord record = model.run(design().row(0).data());
  StreamingBand band(static_cast<std::size_t>(model.layout().time_samples), 100000);
  std::size_t added = 0;
  for (auto _ : state) {
    if (++added == 100000) {
      state.PauseTiming();
      band = StreamingBand(static_cast<std::size_t>(model.layout().time_samples), 100000);
      added = 0;
      state.ResumeTiming();
    }
    band.add(record.curve(0, model.layout().time_samples));
  }
}
BENCHMARK(BM_StreamingBandAdd)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
