// How the contact detection's cost grows with the number of surface particles
// (sim/contact.hpp): a k x k floor of 3 x 3 x 3-particle cubes, each 0.2 mm from its
// neighbours (inside the 0.5 mm contact threshold, so every neighbour pair is in contact),
// for k = 2 ... 32 (104 to 26,624 surface particles, 26 per cube). One iteration is one
// ContactDetector::add_forces call (broad phase grid + narrow phase + forces), as a step
// makes it. The summary after the table gives the exponent b of time ~ surface^b from a
// least-squares fit of log(time) on log(surface particles) over the medians: b near 1 is
// the linear growth the grid is there for (an all-pairs search would give 2).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "sim/contact.hpp"
#include "sim/mesh.hpp"
#include "sim/model.hpp"

namespace {

// k x k cubes of 10 mm, 3 x 3 x 3 particles, gaps of 0.2 mm.
rheo::Model floor_of_cubes(int k) {
  rheo::BlockSpec b;
  b.nx = b.ny = b.nz = 3;
  b.sx = b.sy = b.sz = 0.01;
  b.fix_bottom = false;
  b.plate_top = false;
  b.material.k1 = 1e5;
  b.material.c1 = 1e2;
  b.material.c2 = 1e5;
  const rheo::Model cube = rheo::make_block(b);
  rheo::Model m = cube;
  m.x0.clear();
  m.mass.clear();
  m.flags.clear();
  m.edges.clear();
  m.tetrahedra.clear();
  m.triangles.clear();
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const int first = m.num_particles();
      const int id = static_cast<int>(m.object_names.size());
      m.object_names.push_back("cube" + std::to_string(id));
      for (int p = 0; p < cube.num_particles(); ++p) {
        m.x0.push_back(cube.x0[p] + rheo::Vec3(0.0102 * i, 0.0102 * j, 0.0));
        m.mass.push_back(cube.mass[p]);
        m.flags.push_back(cube.flags[p]);
        m.object.push_back(id);
      }
      for (rheo::Edge e : cube.edges) {
        e.s += first;
        e.e += first;
        m.edges.push_back(e);
      }
      for (auto t : cube.tetrahedra) {
        for (int& v : t) v += first;
        m.tetrahedra.push_back(t);
      }
    }
  }
  m.contact.enabled = true;
  m.contact.penalty = {5e-4, 1000.0, 1.0, 0.3};
  return m;
}

std::map<int, double> g_surface;  // k -> surface particles

void contact(benchmark::State& bench, int k) {
  const rheo::Model m = floor_of_cubes(k);
  rheo::ContactDetector detector(m);
  std::vector<rheo::Vec3> v(m.x0.size(), rheo::Vec3(0.01, 0.0, 0.0)), f(m.x0.size());
  int contacts = 0;
  for (auto _ : bench) {
    std::fill(f.begin(), f.end(), rheo::Vec3::Zero());
    contacts = detector.add_forces(m, m.x0, v, 1e-4, f);
    benchmark::DoNotOptimize(f.data());
  }
  g_surface[k] = detector.surface_vertices();
  bench.SetItemsProcessed(bench.iterations() * detector.surface_vertices());
  bench.counters["surface_particles"] = detector.surface_vertices();
  bench.counters["surface_faces"] = detector.surface_faces();
  bench.counters["contacts"] = contacts;
  bench.counters["candidates"] = static_cast<double>(detector.candidates());
}

// Collects the medians for the summary.
class Summary : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.aggregate_name != "median") continue;
      const std::string name = r.run_name.function_name;
      const int k = std::stoi(name.substr(name.rfind('/') + 1));
      median_us[k] = r.GetAdjustedRealTime();  // in the benchmarks' unit, us
    }
  }
  std::map<int, double> median_us;
};

}  // namespace

int main(int argc, char** argv) {
  for (int k : {2, 4, 8, 16, 32}) {
    benchmark::RegisterBenchmark(("contact/cubes_per_side/" + std::to_string(k)).c_str(), contact, k)
        ->Unit(benchmark::kMicrosecond)
        ->Repetitions(3)
        ->ReportAggregatesOnly(false);
  }
  benchmark::Initialize(&argc, argv);
  Summary summary;
  benchmark::RunSpecifiedBenchmarks(&summary);
  // Least squares of log(t) on log(surface particles) over the medians.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  std::printf("\ncontact detection, median per call:\n");
  for (const auto& [k, us] : summary.median_us) {
    const double s = g_surface[k];
    std::printf("  %2d x %2d cubes: %6.0f surface particles, %10.1f us, %.2f us per surface particle\n",
                k, k, s, us, us / s);
    const double x = std::log(s), y = std::log(us);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  if (n >= 2) {
    const double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    std::printf("  time ~ surface particles^%.2f (least squares over %d sizes)\n", b, n);
  }
  benchmark::Shutdown();
  return 0;
}
