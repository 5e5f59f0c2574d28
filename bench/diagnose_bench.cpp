// Wall time of the measured-data demo: `rheo diagnose data/clay_fast.csv --holdout
// data/clay_slow.csv` without its file output (the baseline and six candidate fits of the
// object model, candidates on all cores, the held-out judgement and the mesh check). Real
// time, because the candidates run in parallel threads; three repetitions, quote the median.
// The target is 90 s on the 2-core machine.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "host/identify/diagnose.hpp"
#include "host/identify/measurement.hpp"

namespace {

void diagnose_demo(benchmark::State& bench) {
  using namespace rheo::identify;
  const std::string dir = RHEO_SOURCE_DIR "/data/";
  const std::vector<Measurement> fit{read_measurement_csv(dir + "clay_fast.csv")};
  const std::vector<Measurement> holdout{read_measurement_csv(dir + "clay_slow.csv")};
  Diagnosis d;
  for (auto _ : bench) {
    d = diagnose(fit, holdout);
    benchmark::DoNotOptimize(d.cause);
  }
  bench.counters["named_second_relaxation_time"] =
      d.cause == Extension::kSecondRelaxationTime ? 1.0 : 0.0;
  bench.counters["candidates"] = static_cast<double>(d.candidates.size());
}

BENCHMARK(diagnose_demo)->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
