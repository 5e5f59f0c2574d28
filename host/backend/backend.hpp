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
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sim/model.hpp"

namespace rheo::backend {

struct Options {
  int lanes = 1;          // in-process fixed-point cores (a remote core reports its own)
  std::string trace_fst;  // rtl: FST waveform file (empty: none)
  std::chrono::milliseconds timeout{10000};  // remote: per link transaction
};

class Backend {
 public:
  virtual ~Backend() = default;
  // What runs, for reports: e.g. "reference (double)", "bit-true model".
  virtual std::string name() const = 0;
  // Takes `model` in `state` for time step dt, replacing whatever ran before (a caller that
  // changes the step continues with load(model, state(), new_dt)). Throws rheo::Error when
  // the model does not fit the backend (fixed-point range, core memories).
  virtual void load(const Model& model, const State& state, double dt) = 0;
  // One step per plate height [m]; the plate force [N] of each step. Throws rheo::Error on
  // numerical trouble (non-finite state, fixed-point overflow flags).
  virtual std::vector<double> run(std::span<const double> plate_z) = 0;
  // The state after the last step: positions, velocities, Voigt lengths and arm extensions
  // (what the backend holds; a relaxation spectrum only where it computes one).
  virtual State state() = 0;
  // Features of the loaded model this backend does not compute (empty: all of it).
  virtual std::vector<std::string> dropped_features() const = 0;
};

// The registry: a backend name, its help text and how it is made. `argument` is the text
// after "name:" (remote:PATH), empty for the others.
struct Registration {
  std::string name;
  bool takes_argument = false;
  std::string help;
  std::function<std::unique_ptr<Backend>(const std::string& argument, const Options&)> make;
};
const std::vector<Registration>& registry();

// Makes the backend `spec` names ("ref", "float", "bittrue", "rtl", "remote:PATH"). Throws
// rheo::Error for an unknown name, listing the accepted ones.
std::unique_ptr<Backend> make_backend(const std::string& spec, const Options& options = {});
// "ref, float, bittrue, rtl or remote:PATH", for help texts and errors.
std::string backend_names();

// The factories of the registry (one file each).
std::unique_ptr<Backend> make_reference_backend(const std::string&, const Options&);
std::unique_ptr<Backend> make_float_backend(const std::string&, const Options&);
std::unique_ptr<Backend> make_device_backend(const std::string& device, const Options&);

}  // namespace rheo::backend
