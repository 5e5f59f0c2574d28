#include "host/driver/cosim.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "hls/fixed_format.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/fst_signals.hpp"
#include "host/driver/verilator_transport.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::driver {
namespace {

constexpr const char* kFieldNames[6] = {"x", "y", "z", "p_x", "p_y", "p_z"};
constexpr std::size_t kMaxReportedMismatches = 10;

}  // namespace

std::string CosimMismatch::describe() const {
  std::ostringstream os;
  os << "step " << step << ", ";
  if (particle < 0)
    os << "plate force word";
  else
    os << "particle " << particle << ", field " << field;
  os << ": RTL " << rtl << " != bit-true " << bittrue;
  return os.str();
}

CosimResult run_cosim(const Scenario& scenario, const CosimOptions& opt) {
  if (opt.steps < 1) throw Error("cosim: steps must be at least 1");
  if (opt.compare_every < 1) throw Error("cosim: compare_every must be at least 1");
  const Model model = scenario.build_model();
  const double dt = scenario.options.dt;
  const State start = initial_state(model);
  const CoreImage image =
      make_core_image(model, start, dt, opt.lanes, FormatDesc{}, opt.maxwell_arm);

  CosimResult res;
  res.particles = image.num_particles;
  res.edges = image.num_edges;
  res.edge_rows = image.edge_rows;
  res.lanes = opt.lanes;
  res.length_unit_m = image.units.length_m;
  res.force_unit_N = image.units.force_N;
  res.dt_s = dt;
  res.dropped_features = image.dropped_features;
  res.cycles_per_step_formula =
      cycles_per_step_formula(image.edge_rows, image.num_particles, opt.lanes);

  VerilatorOptions vo;
  vo.lanes = opt.lanes;
  vo.trace_fst = opt.trace_fst;
  vo.input_idle_prob = opt.input_idle_prob;
  vo.output_stall_prob = opt.output_stall_prob;
  vo.seed = opt.seed;
  vo.maxwell_arm = opt.maxwell_arm;
  auto rtl_transport = std::make_unique<VerilatorTransport>(vo);
  VerilatorTransport* rtl_raw = rtl_transport.get();
  auto bt_transport = std::make_unique<BitTrueTransport>(opt.lanes, opt.maxwell_arm);
  BitTrueTransport* bt_raw = bt_transport.get();
  Device rtl(std::move(rtl_transport));
  Device bittrue(std::move(bt_transport));
  rtl.load(image);
  bittrue.load(image);
  const CoreStatus rtl_start = rtl.read_status(false);

  std::unique_ptr<Simulator> ref;
  if (opt.run_reference) {
    SimOptions so = scenario.options;
    ref = std::make_unique<Simulator>(hardware_model(model, nullptr, opt.maxwell_arm), so);
  }
  const double size = image.extent_m;
  double sq_sum = 0.0;
  long sq_count = 0;
  const int np = image.num_particles;

  long step = 0;
  while (step < opt.steps) {
    const long batch = std::min<long>(opt.compare_every, opt.steps - step);
    const bool traced = !opt.trace_fst.empty() && (opt.trace_steps == 0 || step < opt.trace_steps);
    rtl_raw->set_tracing(traced);
    std::vector<std::int32_t> plate_words(batch);
    std::vector<double> plate_z(batch);
    for (long b = 0; b < batch; ++b) {
      const double t = double(step + b + 1) * dt;
      plate_z[b] = model.height - scenario.protocol.displacement_mm(t) * 1e-3;
      plate_words[b] = static_cast<std::int32_t>(to_x_word(plate_z[b], image, "plate height"));
    }
    const std::vector<std::int32_t> f_bt = bittrue.run(plate_words);
    const std::uint64_t batch_start = rtl_raw->trace_time();
    const std::vector<std::int32_t> f_rtl = rtl.run(plate_words);
    if (traced) res.traced.push_back({step + 1, batch, batch_start, rtl_raw->trace_time()});
    for (long b = 0; b < batch; ++b) {
      if (f_rtl[b] != f_bt[b]) {
        ++res.mismatches;
        if (res.first.size() < kMaxReportedMismatches)
          res.first.push_back({step + b + 1, -1, "plate_force", f_rtl[b], f_bt[b]});
      }
      res.force_fixed_N.push_back(from_f_word(f_bt[b], image));
      if (ref) {
        const StepReport rep = ref->step(plate_z[b]);
        res.force_ref_N.push_back(rep.plate_force_N);
      }
    }
    step += batch;
    // Every particle state word of the RTL against the bit-true model.
    const std::vector<std::int32_t> s_rtl = rtl.read_particle_state(0, np);
    const std::vector<std::int32_t> s_bt = bittrue.read_particle_state(0, np);
    for (int i = 0; i < np; ++i) {
      for (int f = 0; f < 6; ++f) {
        const std::size_t w = std::size_t(i) * 6 + f;
        if (s_rtl[w] != s_bt[w]) {
          ++res.mismatches;
          if (res.first.size() < kMaxReportedMismatches)
            res.first.push_back({step, i, kFieldNames[f], s_rtl[w], s_bt[w]});
        }
      }
    }
    if (ref) {
      const hls::CoreMemory& mem = bt_raw->memory();
      double step_max = 0.0;
      for (int i = 0; i < np; ++i) {
        double e2 = 0.0;
        for (int a = 0; a < 3; ++a) {
          const double d = from_x_word(mem.particles[i].x[a], image) - ref->state().x[i][a];
          e2 += d * d;
        }
        const double e = std::sqrt(e2) / size;
        step_max = std::max(step_max, e);
        sq_sum += e * e;
        ++sq_count;
      }
      res.max_pos_err_rel = std::max(res.max_pos_err_rel, step_max);
      res.final_max_pos_err_rel = step_max;
    }
    if (opt.progress) opt.progress(step);
    if (res.mismatches > 0) break;
  }
  res.steps = step;
  if (sq_count > 0) res.rms_pos_err_rel = std::sqrt(sq_sum / double(sq_count));
  if (ref) {
    double fmax = 0.0, emax = 0.0;
    for (std::size_t i = 0; i < res.force_ref_N.size(); ++i) {
      fmax = std::max(fmax, std::fabs(res.force_ref_N[i]));
      emax = std::max(emax, std::fabs(res.force_fixed_N[i] - res.force_ref_N[i]));
    }
    res.max_force_ref_N = fmax;
    res.max_force_err_rel = fmax > 0.0 ? emax / fmax : emax;
  }
  const CoreStatus rtl_end = rtl.read_status(false);
  res.cycles_per_step_measured =
      double(std::uint32_t(rtl_end.cycles - rtl_start.cycles)) / double(std::max<long>(step, 1));
  res.sim_cycles = rtl_raw->cycles();
  res.sim_cycles_per_s =
      rtl_raw->wall_seconds() > 0 ? double(rtl_raw->cycles()) / rtl_raw->wall_seconds() : 0.0;
  return res;
}

std::string write_trace_gtkw(const CosimResult& r, const CosimOptions& opt,
                             const std::string& filter_command, const std::string& final_fst) {
  namespace fs = std::filesystem;
  if (opt.trace_fst.empty()) throw Error("gtkw: the run wrote no waveform");
  if (r.traced.empty()) throw Error("gtkw: no step of the run is in " + opt.trace_fst);
  const FstContents fst = read_fst_signals(opt.trace_fst);
  if (r.traced.front().start_time < fst.start_time || r.traced.front().end_time > fst.end_time)
    throw Error("gtkw: step " + std::to_string(r.traced.front().first_step) +
                " lies outside the times of " + opt.trace_fst);
  GtkwOptions g;
  g.lanes = r.lanes;
  g.maxwell_arm = opt.maxwell_arm;
  // The RTL implements the hardware format (rtl/rheo_consts_pkg.sv is generated from it).
  g.format = FormatDesc::of<hls::HardwareFormat>();
  g.units = Units{r.length_unit_m, r.force_unit_N, r.dt_s};
  g.filter_command = filter_command;
  g.steps = r.traced;
  g.dump_file = fs::absolute(final_fst.empty() ? opt.trace_fst : final_fst).string();
  const std::string text = make_gtkw(fst.signals, g);
  const std::string path = fs::path(opt.trace_fst).replace_extension(".gtkw").string();
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw Error("cannot write " + path);
  return path;
}

}  // namespace rheo::driver
