// C simulation of the HLS kernel (hls/rheo_kernel.hpp) on a small 3D block pushed by the
// plate: against the double reference model, across lane counts, and across the narrow,
// hardware and wide formats (the kernel is templated on the format).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hls/rheo_kernel.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::driver {
namespace {

constexpr long kSteps = 1500;
// The hardware format tracks the double model to well within 1e-4 of the object size over
// this run (measured about 1e-7; the bound leaves room for other materials).
constexpr double kHardwarePosBoundRel = 1e-4;

Scenario small_block() {
  Scenario s = load_scenario("block5");
  s.block.nx = s.block.ny = s.block.nz = 3;
  return s;
}

double plate_height(const Scenario& s, const Model& m, long step) {
  return m.height - s.protocol.displacement_mm(double(step) * s.options.dt) * 1e-3;
}

// Runs the kernel in format Fmt directly on its memory; returns the max position error
// against the double reference relative to the object size.
template <class Fmt>
double run_format(const Scenario& s) {
  const Model model = s.build_model();
  CoreImage img =
      make_core_image(model, initial_state(model), s.options.dt, 1, FormatDesc::of<Fmt>());
  auto mem = std::make_unique<hls::CoreMemory>();
  load_memory(img, *mem);
  Simulator ref(hardware_model(model), s.options);
  const double size = img.units.length_m * 8.0;
  double worst = 0.0;
  for (long n = 1; n <= kSteps; ++n) {
    const double z = plate_height(s, model, n);
    mem->globals.plate_z = to_x_word(z, img, "plate");
    hls::core_step<Fmt>(*mem);
    ref.step(z);
    EXPECT_EQ(mem->status, 0u) << "step " << n;
    for (int i = 0; i < img.num_particles; ++i) {
      double e2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double d = from_x_word(mem->particles[i].x[a], img) - ref.state().x[i][a];
        e2 += d * d;
      }
      worst = std::max(worst, std::sqrt(e2) / size);
    }
  }
  return worst;
}

TEST(BitTrueCsim, HardwareFormatFollowsTheDoubleReferenceOnAPushedBlock) {
  const double err = run_format<hls::HardwareFormat>(small_block());
  EXPECT_LT(err, kHardwarePosBoundRel);
  RecordProperty("max_pos_err_rel", std::to_string(err));
}

TEST(BitTrueCsim, WiderFormatsAreMoreAccurate) {
  const Scenario s = small_block();
  const double narrow = run_format<hls::NarrowFormat>(s);
  const double hardware = run_format<hls::HardwareFormat>(s);
  const double wide = run_format<hls::WideFormat>(s);
  EXPECT_LT(hardware, narrow);
  EXPECT_LE(wide, hardware);
}

TEST(BitTrueCsim, OneAndTwoLanesGiveIdenticalWords) {
  const Scenario s = small_block();
  const Model model = s.build_model();
  std::vector<std::vector<std::int32_t>> forces, states;
  for (int lanes : {1, 2}) {
    Device dev(std::make_unique<BitTrueTransport>(lanes));
    const CoreImage img = make_core_image(model, initial_state(model), s.options.dt, lanes);
    dev.load(img);
    std::vector<std::int32_t> plate;
    for (long n = 1; n <= 500; ++n)
      plate.push_back(std::int32_t(to_x_word(plate_height(s, model, n), img, "plate")));
    forces.push_back(dev.run(plate));
    states.push_back(dev.read_particle_state(0, img.num_particles));
  }
  EXPECT_EQ(forces[0], forces[1]);
  EXPECT_EQ(states[0], states[1]);
}

// The plate rule on rounded positions. A particle that sat on the plate (at the previous
// step's plate height) stays on it, with its force counted, while its new displacement
// exceeds the plate's step (p.z > lim), as the double reference keeps it while v > V_plate.
// Decided on the rounded position (x.z > plate_z), a held particle whose force moves it
// less than half an X LSB per step beyond the plate landed exactly on the plate and was
// dropped with its force: exact-zero plate forces at large mass scales (issue 40).
TEST(BitTrueCsim, AParticleOnThePlateStaysWhileItMovesFasterThanThePlate) {
  using Fmt = hls::HardwareFormat;
  constexpr int kShift = Fmt::kFracP - Fmt::kFracX;
  hls::MpmGlobals g;
  hls::write_control(g, true, true, false);
  g.plate_z = std::int64_t(5) << Fmt::kFracX;  // 5 Lu
  hls::start_step(g, g.plate_z + 100);         // the plate moves up 100 X LSB this step
  const std::int64_t lim = std::int64_t(100) << kShift;
  hls::MpmParticle on{};
  on.flags = hls::kCorePlate;
  on.minv = hls::Coef{0, 0};  // no velocity change from the force: p.z carries it
  on.x[2] = g.plate_z_prev;
  const std::int64_t f[3] = {0, 0, 1000};
  std::uint32_t status = 0;
  // 3 P LSB faster than the plate: the rounded position lands on the plate; it stays.
  hls::MpmParticle faster = on;
  faster.p[2] = lim + 3;
  EXPECT_EQ(hls::mpm_particle<Fmt>(faster, f, g, &status), f[2]);
  EXPECT_EQ(faster.x[2], g.plate_z);
  EXPECT_EQ(faster.p[2], lim) << "p.z = min(p.z, lim): it moves with the plate";
  // Exactly as fast, or slower: it leaves the plate, and its force is not the plate's.
  for (const std::int64_t p : {lim, lim - 3}) {
    hls::MpmParticle slower = on;
    slower.p[2] = p;
    EXPECT_EQ(hls::mpm_particle<Fmt>(slower, f, g, &status), 0) << "p.z - lim = " << p - lim;
    EXPECT_EQ(slower.x[2], g.plate_z) << "its rounded position is still the plate's";
    EXPECT_EQ(slower.p[2], p);
  }
  // Not on the plate before (one X LSB below it): the position decides, as before.
  hls::MpmParticle below = on;
  below.x[2] = g.plate_z_prev - 1;
  below.p[2] = lim + 3 + (std::int64_t(1) << kShift);
  EXPECT_EQ(hls::mpm_particle<Fmt>(below, f, g, &status), 0);
  EXPECT_EQ(below.x[2], g.plate_z);
  // After a control write the previous height is not known: the position decides.
  hls::MpmGlobals fresh = g;
  hls::write_control(fresh, true, true, false);
  hls::MpmParticle unknown = on;
  unknown.p[2] = lim + 3;
  EXPECT_EQ(hls::mpm_particle<Fmt>(unknown, f, fresh, &status), 0);
  EXPECT_EQ(status, 0u);
}

}  // namespace
}  // namespace rheo::driver
