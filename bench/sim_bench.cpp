// Edge updates per second per core of the double reference model (semi-implicit Euler,
// 3D lattice): block5 (5x5x5, the 2003 paper's PC model) and block15 (15x15x16, its FPGA
// model). One edge update = one edge's force, Voigt-length rate and state update; the
// particle update is included in the time, so the figure is per whole step.
#include <benchmark/benchmark.h>

#include "sim/mesh.hpp"
#include "sim/simulator.hpp"

namespace {

// Bread-dough-like block with 10 mm cubic cells (the built-in block5 scenario's material
// and mass scaling; gravity divided by the mass scale so the weight stays physical).
rheo::Model lattice_block(int nx, int ny, int nz) {
  constexpr double kSpacing = 0.01;  // [m]
  rheo::BlockSpec spec;
  spec.nx = nx;
  spec.ny = ny;
  spec.nz = nz;
  spec.sx = kSpacing * (nx - 1);
  spec.sy = kSpacing * (ny - 1);
  spec.sz = kSpacing * (nz - 1);
  spec.structure = rheo::Structure::kLattice;
  spec.density = 1200.0;
  spec.material.k1 = 5e3;  // [Pa]
  spec.material.c1 = 4e4;  // [Pa s]
  spec.material.c2 = 2e4;  // [Pa s]
  spec.mass_scale = 1e3;
  rheo::Model model = rheo::make_block(spec);
  model.gravity /= spec.mass_scale;
  return model;
}

void run(benchmark::State& bench, const rheo::Model& model) {
  rheo::SimOptions options;
  options.dt = 0.5 * rheo::max_stable_dt(model, rheo::Integrator::kSemiImplicitEuler);
  rheo::Simulator sim(model, options);
  // The plate rests 0.1 mm into the block: contact and plate force are exercised.
  const double plate_z = model.height - 1e-4;
  for (auto _ : bench) {
    const rheo::StepReport r = sim.step(plate_z);
    benchmark::DoNotOptimize(r.plate_force_N);
  }
  bench.SetItemsProcessed(bench.iterations() * model.num_edges());
  bench.counters["edges"] = model.num_edges();
  bench.counters["particles"] = model.num_particles();
}

void BM_Block5(benchmark::State& bench) { run(bench, lattice_block(5, 5, 5)); }
void BM_Block15(benchmark::State& bench) { run(bench, lattice_block(15, 15, 16)); }

BENCHMARK(BM_Block5);
BENCHMARK(BM_Block15);

}  // namespace

BENCHMARK_MAIN();
