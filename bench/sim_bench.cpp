// Edge updates per second per core of the double reference model on the built-in scenarios
// block5 (5x5x5, the 2003 paper's PC model) and block15 (15x15x16, its FPGA model), run as
// `rheo simulate` runs them (see bench_models.hpp). One edge update = one edge's force,
// Voigt-length rate and state update; the particle update is included in the time, so the
// figure is per whole step. Each benchmark runs a fixed number of steps (bench_models.cpp),
// three repetitions; quote the median.
#include <benchmark/benchmark.h>

#include "bench/bench_models.hpp"

namespace {

void run(benchmark::State& bench, const std::string& scenario) {
  rheo::bench::ScenarioLoop loop(scenario);
  for (auto _ : bench) {
    if (loop.at_end()) {
      // Putting the object back at rest is not part of a step.
      bench.PauseTiming();
      loop.restart();
      bench.ResumeTiming();
    }
    benchmark::DoNotOptimize(loop.step());
  }
  bench.SetItemsProcessed(bench.iterations() * loop.model().num_edges());
  bench.counters["edges"] = loop.model().num_edges();
  bench.counters["particles"] = loop.model().num_particles();
  bench.counters["dt_s"] = loop.scenario().options.dt;
}

void register_benchmarks() {
  for (const rheo::bench::BenchModel& m : rheo::bench::bench_models()) {
    benchmark::RegisterBenchmark(("reference/" + m.scenario).c_str(),
                                 [name = m.scenario](benchmark::State& s) { run(s, name); })
        ->Iterations(m.steps)
        ->Repetitions(3)
        ->Unit(benchmark::kMicrosecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
