// Edge updates per second of the CPU model on block5 (5x5x5, the 2003 paper's PC model),
// block15 (15x15x16, its FPGA model) and lattice30 (30x30x30), run as `rheo simulate` runs
// them (see bench_models.hpp): the scalar reference (rheo::Simulator) and the fast path
// (rheo::fast::FastSimulator) with 1 and 2 threads, in one run. One edge update = one
// edge's force, Voigt-length rate and state update; the particle update is included in the
// time, so the figure is per whole step. Each benchmark runs a fixed number of steps
// (bench_models.cpp) in batches of 20 (kBatch), wall time, three repetitions; the summary after the table quotes the medians,
// the ratios between the paths and the fraction of this CPU's divide/sqrt limit
// (divider_limit.hpp), measured in the same run.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench/bench_models.hpp"
#include "bench/divider_limit.hpp"
#include "sim/fast/edge_sweep.hpp"

namespace {

using rheo::bench::CpuPath;

std::string path_name(const CpuPath& p) {
  return p.fast ? "fast/threads:" + std::to_string(p.threads) : "scalar";
}

// Steps per benchmark iteration: a batch in one run() call, as `rheo simulate` hands the
// reference its steps between two CSV rows.
constexpr int kBatch = 20;

void run(benchmark::State& bench, const std::string& scenario, CpuPath path) {
  rheo::bench::ScenarioLoop loop(scenario, path);
  long long steps = 0;
  for (auto _ : bench) {
    if (loop.at_end()) {
      // Putting the object back at rest is not part of a step.
      bench.PauseTiming();
      loop.restart();
      bench.ResumeTiming();
    }
    const long long before = loop.steps_done();
    benchmark::DoNotOptimize(loop.run(kBatch));
    steps += loop.steps_done() - before;
  }
  bench.SetItemsProcessed(steps * loop.model().num_edges());
  bench.counters["edges"] = loop.model().num_edges();
  bench.counters["particles"] = loop.model().num_particles();
  bench.counters["threads"] = path.threads;
  bench.counters["dt_s"] = loop.scenario().options.dt;
  bench.counters["steps"] = static_cast<double>(steps);
}

// One square root and one division per "edge", on a block of values that stays in L1.
constexpr std::size_t kLimitValues = 4096;
constexpr int kLimitRepeats = 64;

void divider_limit(benchmark::State& bench) {
  std::vector<double> in(kLimitValues), out(kLimitValues);
  for (std::size_t i = 0; i < in.size(); ++i) in[i] = 1.0 + 1e-3 * static_cast<double>(i);
  for (auto _ : bench) {
    rheo::bench::sqrt_divide_sweep(in.data(), out.data(), in.size(), kLimitRepeats);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  bench.SetItemsProcessed(bench.iterations() * kLimitValues * kLimitRepeats);
}

const char* kLimitName = "limit/sqrt_and_divide";

void register_benchmarks() {
  benchmark::RegisterBenchmark(kLimitName, divider_limit)
      ->Repetitions(3)
      ->Unit(benchmark::kMicrosecond);
  for (const rheo::bench::BenchModel& m : rheo::bench::bench_models()) {
    for (const CpuPath path : {CpuPath{false, 1}, CpuPath{true, 1}, CpuPath{true, 2}}) {
      // The fast path runs more steps, so that each repetition still takes a measurable time.
      const long long steps = (path.fast ? 4 * m.steps : m.steps) / kBatch;
      benchmark::RegisterBenchmark((path_name(path) + "/" + m.scenario).c_str(),
                                   [name = m.scenario, path](benchmark::State& s) {
                                     run(s, name, path);
                                   })
          ->Iterations(steps)
          ->Repetitions(3)
          ->UseRealTime()
          ->Unit(benchmark::kMicrosecond);
    }
  }
}

// The console table, and the medians kept for the summary.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.aggregate_name != "median") continue;
      const auto rate = r.counters.find("items_per_second");
      if (rate != r.counters.end()) median_[r.run_name.function_name] = rate->second.value;
    }
  }
  double median(const std::string& name) const {
    const auto it = median_.find(name);
    return it == median_.end() ? 0.0 : it->second;
  }

 private:
  std::map<std::string, double> median_;
};

void print_summary(const SummaryReporter& r) {
  const double limit = r.median(kLimitName);
  std::printf("\nSummary (medians of 3 repetitions, edge updates per second, M = 1e6)\n");
  std::printf("divide/sqrt limit of one core: %.0f M/s (one sqrt and one divide per edge, %s)\n",
              limit / 1e6, rheo::fast::sweep_target().c_str());
  std::printf("%-10s %10s %12s %8s %14s %8s %16s %13s\n", "model", "scalar", "fast 1 thr",
              "x scalar", "fast 2 thr", "x 1 thr", "2 thr per core", "1 thr / limit");
  for (const rheo::bench::BenchModel& m : rheo::bench::bench_models()) {
    const double scalar = r.median("scalar/" + m.scenario);
    const double one = r.median("fast/threads:1/" + m.scenario);
    const double two = r.median("fast/threads:2/" + m.scenario);
    if (scalar <= 0.0 || one <= 0.0 || two <= 0.0) continue;  // filtered out
    std::printf("%-10s %8.0f M %10.0f M %7.2fx %12.0f M %7.2fx %14.0f M %12.1f %%\n",
                m.scenario.c_str(), scalar / 1e6, one / 1e6, one / scalar, two / 1e6, two / one,
                two / 2e6, limit > 0.0 ? 100.0 * one / limit : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  print_summary(reporter);
  benchmark::Shutdown();
  return 0;
}
