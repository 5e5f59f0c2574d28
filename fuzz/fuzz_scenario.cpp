// libFuzzer harness for scenario files (sim/scenario.cpp): the input is the text of a JSON
// scenario as `rheo simulate|fixed|cosim --scenario FILE` would read it (load_scenario).
// An accepted scenario then goes where the commands take it, for models small enough to
// keep an execution fast: the step count, the plate protocol, the model build and
// validation, a few reference steps, and the conversion into the core's fixed-point image
// (the path where doubles from the file become integer words).
//
// rheo::Error is the documented way a scenario is refused and is expected. Everything else is
// a finding: a sanitizer report (a NaN or huge double converted to an integer included:
// float-cast-overflow) or another exception, which escapes to libFuzzer.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "sim/model.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace {

// Larger models are parsed and checked but not built: building and stepping them is the
// simulator's cost, not the reader's, and would slow the fuzzer down by orders of magnitude.
constexpr long kMaxParticlesToBuild = 125;
constexpr int kSteps = 3;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

template <class F>
void expect_error_or_success(F&& f) {
  try {
    f();
  } catch (const rheo::Error&) {
  }
}

void use(const rheo::Scenario& s) {
  check(std::isfinite(s.options.dt) && s.options.dt > 0.0);
  check(!s.protocol.t.empty() && s.protocol.t.size() == s.protocol.plate_mm.size());
  expect_error_or_success([&] { check(s.default_steps() >= 1); });
  (void)s.protocol.phases();
  const double end = s.protocol.duration();
  for (double t : {-1.0, 0.0, 0.5 * end, end, 2.0 * end}) (void)s.protocol.displacement_mm(t);
  for (long long step : {0LL, 1LL, 1000LL}) (void)s.plate_mm(step);

  long particles = long(s.block.nx) * s.block.ny * s.block.nz;
  for (const rheo::ObjectSpec& o : s.objects) particles += long(o.block.nx) * o.block.ny * o.block.nz;
  if (particles > kMaxParticlesToBuild) return;
  expect_error_or_success([&] {
    const rheo::Model model = s.build_model();
    rheo::Simulator sim(model, s.options);
    for (int step = 0; step < kSteps; ++step) sim.step(s.plate_z(model, step));
  });
  expect_error_or_success([&] {
    const rheo::Model model = s.build_model();
    const rheo::hls::EdgeElement& element = rheo::driver::edge_element_for(model);
    const rheo::Model hw = rheo::driver::hardware_model(model, nullptr, element);
    const rheo::State state = rheo::initial_state(hw);
    const auto image = rheo::driver::make_core_image(hw, state, s.options.dt, 1,
                                                     rheo::driver::FormatDesc{}, element);
    (void)rheo::driver::image_frames(image);
    for (int step = 0; step < kSteps; ++step) {
      (void)rheo::driver::to_x_word(s.plate_z(hw, step), image, "plate height");
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    use(rheo::parse_scenario(text, "fuzz.json"));
  } catch (const rheo::Error&) {
  }
  return 0;
}
