// The fixed-point cores behind the Backend interface: the bit-true model, the verilated
// RTL and a remote core, all driven through driver::Device with the frames of the core's
// stream format. The model is converted by driver::hardware_model (features the core lacks
// are listed, never silently dropped) and driver::make_core_image; the core variant is the
// one with as many Maxwell arms as the model's materials have (driver::edge_element_for).
#include <algorithm>
#include <cmath>
#include <memory>

#include "host/backend/backend.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/device_factory.hpp"
#include "host/driver/tool_regs.hpp"
#include "sim/error.hpp"

namespace rheo::backend {
namespace {

class DeviceBackend : public Backend {
 public:
  DeviceBackend(std::string device, const Options& options)
      : device_spec_(std::move(device)), options_(options) {}

  std::string name() const override { return name_.empty() ? device_spec_ : name_; }
  std::string arithmetic() const override {
    return "fixed-point core: bittrue, rtl and remote give the same numbers";
  }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    const double dt = options.dt;
    // The core variant whose edge element computes the model's edges.
    const hls::EdgeElement& element = driver::edge_element_for(model);
    const bool arm = element.has_maxwell_arm();
    const Model hw = driver::hardware_model(model, &dropped_, element);
    check_hardware_step(hw, options, dropped_);
    hw_ = hw;
    if (!device_ || element != element_) {
      link::DeviceOptions o;
      o.lanes = options_.lanes;
      o.element = element;
      o.trace_fst = options_.trace_fst;
      o.timeout = options_.timeout;
      o.input_idle_prob = options_.input_idle_prob;
      o.output_stall_prob = options_.output_stall_prob;
      o.seed = options_.seed;
      link::OpenedDevice opened = link::make_device(device_spec_, o);
      device_ = std::move(opened.device);
      lanes_ = opened.lanes;
      name_ = opened.name;
      element_ = element;
    }
    image_ = driver::make_core_image(hw, state, dt, lanes_, driver::FormatDesc{}, element);
    check_gravity_word(hw, dt, image_.units.length_m, image_.format.frac_p, image_.globals.g,
                       name());
    plate_.load(hw, dt, std::ldexp(image_.units.length_m, -image_.format.frac_x), name());
    try {
      device_->load(image_);
    } catch (const Error& e) {
      // A remote core's variant is the server's choice; the usual cause of a refused image.
      if (!arm || !device_spec_.starts_with("remote:")) throw;
      throw Error(std::string(e.what()) + "; the model has " +
                  std::to_string(element.maxwell_arms) +
                  " Maxwell arm(s): the server's core needs them too (rheo "
                  "cosim-server --element " + std::string(element.name) + ")");
    }
    t_ = state.t;
    dt_ = dt;
    tool_posed_ = false;
    if (!hw_.tools.empty()) {
      // The core's tool unit returns the reaction force only.
      dropped_.push_back("the tool's reaction torque and contact count (the core's tool unit "
                         "returns the reaction force; tools.csv has 0 for them)");
    }
  }

  // A model with one tool on a core with the tool unit (hardware_model refused anything
  // else): per step, the tool's registers for its move, one step, the reaction read back.
  std::vector<double> run_tools(std::span<const double> plate_z, std::span<const ToolPose> poses,
                                std::vector<ToolReaction>& reactions) override {
    const driver::CoreImage& img = loaded();
    const std::size_t tools = hw_.tools.size();
    if (tools == 0) return Backend::run_tools(plate_z, poses, reactions);
    plate_.check(plate_z);
    if (poses.size() != plate_z.size() * tools) {
      throw Error(name() + ": " + std::to_string(poses.size()) + " tool poses for " +
                  std::to_string(plate_z.size()) + " steps of " + std::to_string(tools) +
                  " tools");
    }
    // The core returns the reaction force, neither its torque nor how many particles
    // touch: the count says it is not known rather than 0 (a haptic client read "no
    // contact" under a 2 N reaction).
    ToolReaction unknown;
    unknown.contacts = ToolReaction::kContactsNotCounted;
    reactions.assign(poses.size(), unknown);
    std::vector<double> force;
    force.reserve(plate_z.size());
    for (std::size_t k = 0; k < plate_z.size(); ++k) {
      const ToolPose& now = poses[k];
      if (!now.position.allFinite() || !std::isfinite(now.q)) {
        throw Error(name() + ": the pose of tool 0 (\"" + hw_.tools[0].name +
                    "\") is not finite at step " + std::to_string(k));
      }
      // The first pose ever given: the tool was there before (it starts at rest), as in
      // the reference (Simulator::set_tool_poses).
      if (!tool_posed_) tool_before_ = now;
      tool_posed_ = true;
      device_->write_tool(driver::encode_tool(hw_.tools[0], 0, tool_before_, now, img));
      const std::int32_t plate =
          static_cast<std::int32_t>(driver::to_x_word(plate_z[k], img, "plate height"));
      force.push_back(driver::from_f_word(device_->run({plate})[0], img));
      const std::array<std::int32_t, 3> r = device_->read_tool_reaction();
      reactions[k].force = Vec3(driver::from_f_word(r[0], img), driver::from_f_word(r[1], img),
                                driver::from_f_word(r[2], img));
      tool_before_ = now;
      t_ += dt_;
    }
    return force;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    const driver::CoreImage& img = loaded();
    plate_.check(plate_z);
    std::vector<std::int32_t> words;
    words.reserve(plate_z.size());
    for (double z : plate_z) {
      words.push_back(static_cast<std::int32_t>(driver::to_x_word(z, img, "plate height")));
    }
    const std::vector<std::int32_t> got = device_->run(words);
    std::vector<double> force;
    force.reserve(got.size());
    for (std::int32_t w : got) force.push_back(driver::from_f_word(w, img));
    t_ += dt_ * static_cast<double>(plate_z.size());
    return force;
  }

  State particle_state() override {
    const driver::CoreImage& img = loaded();
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
    const driver::CoreImage& img = loaded();
    State s = particle_state();
    const int slots = static_cast<int>(img.edges.size());
    const std::vector<std::int32_t> d = device_->read_voigt_lengths(0, slots);
    std::vector<std::vector<std::int32_t>> m(element_.maxwell_arms);
    for (int j = 0; j < element_.maxwell_arms; ++j) m[j] = device_->read_arm_extensions(j, 0, slots);
    s.d.resize(img.num_edges);
    for (int k = 0; k < img.num_edges; ++k) s.d[k] = driver::from_x_word(d[img.edge_slot[k]], img);
    driver::read_arm_extensions(
        hw_, img, [&m](int j, int slot) { return std::int64_t(m[j][slot]); }, s);
    return s;
  }

  std::vector<std::string> dropped_features() const override { return dropped_; }
  void check_plate_heights(std::span<const double> plate_z) override { plate_.check_path(plate_z); }

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
  const driver::CoreImage& loaded() const {
    if (!device_) throw Error(device_spec_ + " backend: no model loaded");
    return image_;
  }

  std::string device_spec_;
  Options options_;
  std::unique_ptr<driver::Device> device_;
  driver::CoreImage image_;
  std::vector<std::string> dropped_;
  std::string name_;
  int lanes_ = 1;
  hls::EdgeElement element_ = hls::kThreeElement;
  Model hw_;  // the model the core computes (arm extensions map back into its state)
  PlateResolution plate_;
  double t_ = 0.0, dt_ = 0.0;
  bool tool_posed_ = false;  // a tool pose was given since the load
  ToolPose tool_before_;     // the tool's pose in the last step
};

}  // namespace

std::unique_ptr<Backend> make_device_backend(const std::string& device, const Options& options) {
  // The core itself is opened at the first load (its variant follows the model); the
  // name is checked here so that a misspelt one fails before any work.
  if (!link::is_device_backend(device)) throw Error("backend '" + device + "': not a device");
  return std::make_unique<DeviceBackend>(device, options);
}

}  // namespace rheo::backend
