// One interface for every way the project computes a model: the double reference
// (rheo::Simulator), the same step in float, the bit-true fixed-point core, the verilated
// RTL core and a core behind `rheo cosim-server`. A caller loads a model in a state for a
// time step, runs steps with one plate height each and gets the plate force of each step,
// and reads the particle state back; it never needs to know which backend it drives.
//
// Adding a backend: one class implementing Backend in its own file, and one line in the
// registry (backend.cpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/fast/fast_simulator.hpp"
#include "sim/model.hpp"
#include "sim/simulator.hpp"

namespace rheo::backend {

struct Options {
  int lanes = 1;          // in-process fixed-point cores (a remote core reports its own)
  std::string trace_fst;  // rtl: FST waveform file (empty: none)
  std::chrono::milliseconds timeout{10000};  // remote: per link transaction
  // rtl: random idle cycles on the core's input stream and random back-pressure on its
  // output stream (probability per clock), from this seed.
  double input_idle_prob = 0.0;
  double output_stall_prob = 0.0;
  std::uint64_t seed = 1;
  // ref: the fast CPU path (falling back to the scalar model, with a note in describe(), for
  // what it does not compute) or the scalar reference model.
  fast::CpuOptions cpu;
};

// The clocks of a fixed-point core: its own cycle counter (status register, all cores) and,
// for a simulated one (rtl), the clocks simulated and the wall time spent on them.
struct CoreClock {
  std::uint32_t core_cycles = 0;  // compute clocks since reset (wraps at 2^32)
  std::uint64_t sim_cycles = 0;
  double sim_wall_s = 0.0;
};

class Backend {
 public:
  virtual ~Backend() = default;
  // What runs, for reports: e.g. "reference (double)", "bit-true model".
  virtual std::string name() const = 0;
  // The arithmetic the numbers come from, the same for backends that give identical numbers
  // (bit-true, RTL and remote): e.g. "double-precision reference model". Output files carry
  // it, so that identical runs write identical files.
  virtual std::string arithmetic() const = 0;
  // Takes `model` in `state` with these step options, replacing whatever ran before (a
  // caller that changes the step continues with load(model, state(), new_options)). Throws
  // rheo::Error when the model does not fit the backend (fixed-point range, core memories)
  // or the step is unstable (the reference checks options.check_stability). Options a
  // backend cannot honour (the cores step semi-implicit Euler only) are named by
  // dropped_features(), never silently replaced.
  virtual void load(const Model& model, const State& state, const SimOptions& options) = 0;
  // The same with the default integrator and step size dt.
  void load(const Model& model, const State& state, double dt) {
    SimOptions o;
    o.dt = dt;
    load(model, state, o);
  }
  // One step per plate height [m]; the plate force [N] of each step. Throws rheo::Error on
  // numerical trouble (non-finite state, fixed-point overflow flags).
  virtual std::vector<double> run(std::span<const double> plate_z) = 0;
  // The same for a model with tools (Model::tools, docs/contact.md): `poses` holds every
  // tool's pose for each step (plate_z.size() x tools, step after step); `reactions`
  // receives the reaction on every tool at every step in the same layout. A backend that
  // does not compute tools refuses such a model in load(); this default throws.
  virtual std::vector<double> run_tools(std::span<const double> plate_z,
                                        std::span<const ToolPose> poses,
                                        std::vector<ToolReaction>& reactions);
  // The state after the last step: positions, velocities, Voigt lengths and arm extensions
  // (what the backend holds; a relaxation spectrum only where it computes one).
  virtual State state() = 0;
  // Positions and velocities after the last step, the other fields of State left empty: what
  // a comparison of particles needs. A core then reads back only its particle words (a
  // core with Maxwell arms has many times more edge words than particle words).
  virtual State particle_state() { return state(); }
  // The state after the last step where the backend keeps it in host memory in double
  // precision (the reference): no read-back from a core (the fast CPU path converts its
  // layout once after each run). nullptr where state() has to convert or read it from a
  // core; callers then read it only where they need it.
  virtual const State* resident_state() const { return nullptr; }
  // Features of the loaded model this backend does not compute (empty: all of it).
  virtual std::vector<std::string> dropped_features() const = 0;
  // What the backend is beyond its name, for reports (e.g. a fixed-point format's widths and
  // units; the reference's CPU path as "cpu_path", and as "cpu_note" why it is not the fast
  // one); empty where there is nothing to add.
  virtual nlohmann::json describe() const { return nlohmann::json::object(); }
  // The model as this backend computes it, from the model a caller would load: a core that
  // needs another form of the same model (the sweep core: every edge from its lower to its
  // higher particle) says so here, so that cores compared word for word run the same words.
  virtual Model prepared(const Model& model) const { return model; }
  // The core's clocks where the backend is a core (empty for the reference and float).
  virtual std::optional<CoreClock> clock() { return std::nullopt; }
  // Clocks per step by the core's documented formula, where the backend knows it from the
  // loaded model (empty: the caller uses rheo_core's, driver::cycles_per_step_formula).
  virtual std::optional<long> cycles_per_step_formula() const { return std::nullopt; }
  // Clocks of one run command of `steps` steps by that formula (empty: steps x the clocks per
  // step): a core whose steps overlap within a command (the sweep core) says so here.
  virtual std::optional<long> command_cycles_formula(long steps) const {
    const std::optional<long> one = cycles_per_step_formula();
    if (!one) return std::nullopt;
    return *one * steps;
  }
  // Refuses, before any step, plate heights whose plate force this backend cannot resolve
  // (PlateResolution below: a float or fixed-point format, the penetration plate rule, a
  // plate too slow for the particles' mass); throws rheo::Error naming the mass scale, the
  // format's force step and the limit. run() checks its heights the same way before it
  // steps them; a caller that knows the whole plate path calls this first, so that a run
  // is refused before its first step. The reference resolves every plate: no-op.
  virtual void check_plate_heights(std::span<const double> /*plate_z*/) {}
  // Waveform (rtl with Options::trace_fst): on or off for the steps that follow, and the
  // waveform's current time, to mark which steps it covers.
  virtual void set_tracing(bool /*on*/) {}
  virtual std::uint64_t trace_time() const { return 0; }
};

// The registry: a backend name, its help text and how it is made. `argument` is the text
// after "name:" (remote:PATH, fixed:FORMAT), empty for the others.
struct Registration {
  std::string name;
  std::string argument;  // what follows "name:", e.g. "PATH"; empty: no argument
  std::string help;
  std::function<std::unique_ptr<Backend>(const std::string& argument, const Options&)> make;
};
const std::vector<Registration>& registry();

// Makes the backend `spec` names ("ref", "float", "bittrue", "rtl", "remote:PATH"). Throws
// rheo::Error for an unknown name, listing the accepted ones.
std::unique_ptr<Backend> make_backend(const std::string& spec, const Options& options = {});
// "ref, float, bittrue, rtl, remote:PATH, sweep, sweep-bittrue or fixed:FORMAT", for help texts and errors.
std::string backend_names();
// Whether `spec` names a registered backend (its argument, e.g. a format, is checked when
// the backend is made).
bool is_backend_spec(const std::string& spec);

// For backends that step the hardware's rule (semi-implicit Euler): checks the step of
// `options` on `model` as the reference does (check_time_step) and names an integrator it
// cannot honour in `dropped`.
void check_hardware_step(const Model& model, const SimOptions& options,
                         std::vector<std::string>& dropped);

// The plate force resolution of a format (docs/backends.md, "Plate force resolution").
// With the penetration plate rule a particle the plate held stays on it while it pushes,
// i.e. while its force f moves it dt^2 f / m beyond the plate's step
// in the step; the format's position word resolves that only down to its resolution dz at
// the plate, so the rule resolves a plate particle's force in steps of m dz / dt^2 (0.69 N
// per particle for block5 in float at mass_scale 3e5). The force it must resolve is at
// least what the particle's edges exert at the plate's speed V: their instantaneous
// damping over one step, the sum of c2 (c1 + k1 dt) / (c1 + c2 + k1 dt) (the cores'
// folded ct; c2_min for a nonlinear damper), times V, the viscous part of the plate force,
// present from the first step of contact. Plate heights whose fastest speed leaves that
// force below kMargin force steps for some plate particle are refused. The
// hold-while-pushing rule keeps a held particle while its force pushes, whatever its
// rounded position: it needs no such resolution and is not checked.
class PlateResolution {
 public:
  // Measured on 20 block5 variants (k1 2e4..2e8 Pa, mass_scale 300..3e8, float and
  // bittrue, 2,000 push steps, with the plate rule's tie counted): where the damper force
  // was 4.6 or more force steps, the largest plate force error was 3.1e-4 of the peak; at
  // 3.0, 1.6e-4; at 2.3, 19 %; at 1.7 and below, up to 100 % (docs/backends.md).
  static constexpr double kMargin = 4.0;

  // For the model a backend computes (driver::hardware_model's), its step dt [s] and its
  // position word's resolution at the plate's height [m]; `format` names the arithmetic
  // in messages (e.g. "float (24-bit significand)"); `double_precision`: the format is the
  // reference's own (no wider backend to suggest).
  void load(const Model& model, double dt, double position_lsb_m, std::string format,
            bool double_precision = false);
  // Throws rheo::Error when the plate's fastest speed since the load, these heights
  // included, is above 0 and leaves a plate particle's damper force below kMargin force
  // steps. check() takes the heights of the next steps (continuing from the last height it
  // saw); check_path() a whole plate path ahead of the run (it does not move the last
  // height).
  void check(std::span<const double> plate_z);
  void check_path(std::span<const double> plate_z);
  // The slowest plate speed whose forces the format resolves [m/s] (0: nothing to
  // resolve), and the force step [N] of the particle that sets it.
  double slowest_speed_m_s() const { return slowest_speed_; }
  double force_step_N() const { return force_step_; }
  // {"plate_force_step_N", "slowest_resolved_plate_speed_m_s"} for describe().
  nlohmann::json describe() const;

 private:
  void refuse_if_unresolved() const;

  std::string format_;
  double mass_scale_ = 1.0, dt_ = 0.0, lsb_ = 0.0;
  double slowest_speed_ = 0.0;  // max over plate particles of force step / (kMargin damping)
  double force_step_ = 0.0, damping_ = 0.0, mass_ = 0.0;  // of that particle
  int particle_ = -1;
  bool double_precision_ = false;
  double fastest_ = 0.0;  // plate speed since the load
  double last_z_ = 0.0;
  bool have_last_ = false;
};

// The position word's resolution of single precision at height z [m]: the spacing of
// floats in [2^e, 2^(e+1)) holding |z|.
double float_position_lsb(double z);
// The spacing of a floating-point format with a `significand_bits`-bit significand at z
// (24: float, 53: double).
double position_lsb(double z, int significand_bits);

// For fixed-point images: throws rheo::Error when the core's gravity word (g dt^2 / Lu in
// the velocity format) is off from its exact value by more than 1 % (mass-scaled gravity
// g / mass_scale rounds towards zero: at mass_scale 3e7 on block5 it is 0.14 LSB, and the
// core computed the object without its weight). `format` names the arithmetic.
void check_gravity_word(const Model& model, double dt, double length_unit_m, int frac_p,
                        const std::int64_t word[3], const std::string& format);

// The factories of the registry (one file each).
std::unique_ptr<Backend> make_reference_backend(const std::string&, const Options&);
std::unique_ptr<Backend> make_float_backend(const std::string&, const Options&);
std::unique_ptr<Backend> make_device_backend(const std::string& device, const Options&);
std::unique_ptr<Backend> make_fixed_format_backend(const std::string& format, const Options&);
std::unique_ptr<Backend> make_sweep_backend(const std::string& spec, const Options&);

// The formats of make_fixed_format_backend: the fractional position widths of the sweep
// (nearest or truncating rounding, full-width operands), and a format's spec text
// ("fixed:q27_nearest_op18"; operand_bits 0 = full width).
std::vector<int> fixed_sweep_frac_x();
std::string fixed_format_spec(int frac_x, bool truncate, int operand_bits);

}  // namespace rheo::backend
