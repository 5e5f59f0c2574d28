#include "host/driver/link/backend_run.hpp"

#include "host/driver/core_image.hpp"
#include "host/driver/link/device_factory.hpp"
#include "host/driver/link/streaming_run.hpp"

namespace rheo::link {

BackendRunSummary run_scenario_on_backend(const Scenario& scenario,
                                          const BackendRunOptions& options,
                                          const BackendRunCallbacks& callbacks) {
  DeviceOptions backend_options;
  backend_options.lanes = options.lanes;
  backend_options.timeout = options.timeout;
  OpenedDevice backend = make_device(options.backend, backend_options);
  const Model model = scenario.build_model();
  const double dt = scenario.options.dt;
  const driver::CoreImage image =
      driver::make_core_image(model, initial_state(model), dt, backend.lanes);
  backend.device->load(image);

  // Step s (0-based) consumes the plate position at the end of the step, as in rheo cosim.
  auto time_of = [dt](std::uint64_t s) { return double(s + 1) * dt; };
  StreamingOptions o;
  o.steps = options.steps;
  o.num_particles = image.num_particles;
  o.state_every = options.state_every;
  o.window_steps = options.window_steps;
  o.chunk_steps = options.chunk_steps;
  StreamingCallbacks c;
  c.plate_word = [&](std::uint64_t s) {
    const double z = scenario.plate_z(model, static_cast<long long>(s + 1));
    return static_cast<std::int32_t>(driver::to_x_word(z, image, "plate height"));
  };
  c.force = [&](std::uint64_t s, std::int32_t word) {
    if (!callbacks.step) return;
    const double t = time_of(s);
    callbacks.step(
        {s + 1, t, scenario.protocol.displacement_mm(t), driver::from_f_word(word, image)});
  };
  c.state = [&](std::uint64_t done, std::span<const std::int32_t> words) {
    if (!callbacks.positions && !callbacks.state) return;
    std::vector<Vec3> x(static_cast<std::size_t>(image.num_particles)), v(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (int a = 0; a < 3; ++a) {
        x[i][a] = driver::from_x_word(words[6 * i + a], image);
        v[i][a] = driver::from_p_word(words[6 * i + 3 + a], image);
      }
    }
    if (callbacks.positions) callbacks.positions(done, x);
    if (callbacks.state) callbacks.state(done, x, v);
  };
  run_streaming(backend.device->transport(), o, c);
  return {backend.name, backend.lanes, image.dropped_features};
}

}  // namespace rheo::link
