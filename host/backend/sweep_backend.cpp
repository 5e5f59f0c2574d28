// The sweep core behind the Backend interface: its verilated RTL with the board SRAM models
// ("sweep") or its bit-true model ("sweep-bittrue"), driven through driver::Device with the
// frames of host/driver/sweep_image.hpp. The model is the hardware's three-element model
// (what the sweep core does not compute is listed, never silently dropped) with every edge
// running from its lower to its higher particle (prepared()), which is also the model a
// core compared with it word for word has to run.
#include <cmath>
#include <memory>

#include "host/backend/backend.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/device_factory.hpp"
#include "host/driver/sweep_image.hpp"
#include "sim/error.hpp"

namespace rheo::backend {
namespace {

class SweepBackend : public Backend {
 public:
  SweepBackend(std::string spec, const Options& options) : spec_(std::move(spec)), options_(options) {}

  std::string name() const override { return name_.empty() ? spec_ : name_; }
  std::string arithmetic() const override {
    return "fixed-point core: bittrue, rtl and remote give the same numbers";
  }
  Model prepared(const Model& model) const override {
    return driver::orient_edges_low_to_high(model);
  }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    dropped_.clear();
    if (!model.tools.empty()) {
      throw Error("the model has tools, and the sweep core has no tool unit (docs/hardware.md, "
                  "\"Contact and tools\"); run it on --backend ref, bittrue or rtl");
    }
    const Model hw = driver::hardware_model(model, &dropped_, hls::kThreeElement);
    check_hardware_step(hw, options, dropped_);
    if (!device_) {
      link::DeviceOptions o;
      o.trace_fst = options_.trace_fst;
      o.input_idle_prob = options_.input_idle_prob;
      o.output_stall_prob = options_.output_stall_prob;
      o.seed = options_.seed;
      link::OpenedDevice opened = link::make_sweep_device(spec_, o);
      device_ = std::move(opened.device);
      name_ = opened.name;
      shape_.lanes = opened.lanes;
    }
    image_ = driver::make_sweep_image(prepared(hw), state, options.dt, shape_);
    const driver::CoreImage& base = image_.base;
    check_gravity_word(hw, options.dt, base.units.length_m, base.format.frac_p, base.globals.g,
                       name());
    plate_.load(hw, options.dt, std::ldexp(base.units.length_m, -base.format.frac_x), name());
    device_->load_frames(driver::sweep_frames(image_), shape_.lanes, true);
    loaded_ = true;
    t_ = state.t;
    dt_ = options.dt;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    const driver::CoreImage& img = loaded().base;
    plate_.check(plate_z);
    std::vector<std::int32_t> words;
    words.reserve(plate_z.size());
    for (double z : plate_z)
      words.push_back(static_cast<std::int32_t>(driver::to_x_word(z, img, "plate height")));
    const std::vector<std::int32_t> got = device_->run(words);
    std::vector<double> force;
    force.reserve(got.size());
    for (std::int32_t w : got) force.push_back(driver::from_f_word(w, img));
    t_ += dt_ * static_cast<double>(plate_z.size());
    return force;
  }

  State particle_state() override {
    const driver::CoreImage& img = loaded().base;
    State s;
    s.t = t_;
    const int n = img.num_particles;
    const std::vector<std::int32_t> xp = device_->read_particle_state(0, n);
    s.x.resize(n);
    s.v.resize(n);
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        s.x[i][a] = driver::from_x_word(xp[6 * i + a], img);
        s.v[i][a] = driver::from_p_word(xp[6 * i + 3 + a], img);
      }
    }
    return s;
  }

  State state() override {
    const driver::SweepImage& si = loaded();
    const driver::CoreImage& img = si.base;
    State s = particle_state();
    // Each lane's Voigt lengths in stream order, mapped back to the model's edges.
    std::vector<std::vector<std::int32_t>> d(si.lane.size());
    for (std::size_t j = 0; j < si.lane.size(); ++j)
      d[j] = device_->read_voigt_lengths(int(j) << hls::kSweepSlotLaneShift,
                                         int(si.lane[j].stream.size()));
    s.d.resize(img.num_edges);
    for (int k = 0; k < img.num_edges; ++k) {
      const std::uint32_t slot = si.edge_slot[k];
      s.d[k] = driver::from_x_word(
          d[slot >> hls::kSweepSlotLaneShift][slot & ((1u << hls::kSweepSlotLaneShift) - 1)], img);
    }
    return s;
  }

  std::vector<std::string> dropped_features() const override { return dropped_; }
  void check_plate_heights(std::span<const double> plate_z) override { plate_.check_path(plate_z); }

  nlohmann::json describe() const override {
    if (!loaded_) return nlohmann::json::object();
    nlohmann::json lanes = nlohmann::json::array();
    for (const driver::SweepLaneImage& l : image_.lane) {
      if (l.count == 0) continue;
      lanes.push_back({{"first", l.first},
                       {"particles", l.count},
                       {"ghost_particles", l.ghost},
                       {"start_delay", l.delay},
                       {"cross_edges", l.cross_edges},
                       {"own_edges", l.own_edges},
                       {"slots", l.slots}});
    }
    nlohmann::json offsets = nlohmann::json::array();
    for (std::uint32_t o : image_.offset)
      if (o != 0) offsets.push_back(o);
    return {{"core", "sweep"},
            {"lanes", shape_.lanes},
            {"lanes_used", image_.lanes_used},
            {"cycles_per_step_formula", image_.cycles_per_step},
            // Steps of one command start this many clocks apart (0: after the last one's force).
            {"period", image_.period},
            {"index_offsets", offsets},
            {"edge_classes", image_.class_len.size()},
            {"mass_classes", image_.mass_minv.size()},
            {"slabs", lanes}};
  }

  std::optional<long> cycles_per_step_formula() const override {
    if (!loaded_) return std::nullopt;
    return image_.cycles_per_step;
  }

  std::optional<long> command_cycles_formula(long steps) const override {
    if (!loaded_) return std::nullopt;
    return hls::sweep_command_cycles(image_.cycles_per_step, image_.period, steps);
  }

  std::optional<CoreClock> clock() override {
    loaded();
    CoreClock c;
    c.core_cycles = device_->read_status(false).cycles;
    c.sim_cycles = device_->transport().cycles();
    c.sim_wall_s = device_->transport().wall_seconds();
    return c;
  }
  void set_tracing(bool on) override {
    if (device_) device_->transport().set_tracing(on);
  }
  std::uint64_t trace_time() const override {
    return device_ ? device_->transport().trace_time() : 0;
  }

 private:
  const driver::SweepImage& loaded() const {
    if (!loaded_) throw Error(spec_ + " backend: no model loaded");
    return image_;
  }

  std::string spec_;
  Options options_;
  std::unique_ptr<driver::Device> device_;
  driver::SweepCoreShape shape_;
  driver::SweepImage image_;
  bool loaded_ = false;
  std::vector<std::string> dropped_;
  PlateResolution plate_;
  std::string name_;
  double t_ = 0.0, dt_ = 0.0;
};

}  // namespace

std::unique_ptr<Backend> make_sweep_backend(const std::string& spec, const Options& options) {
  return std::make_unique<SweepBackend>(spec, options);
}

}  // namespace rheo::backend
