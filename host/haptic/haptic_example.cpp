// Example haptic client (docs/haptics.md): moves a sphere tool into clay and back through
// `rheo haptic-server`, one pose per step as a haptic device's servo loop would, and reports
// the loop's rate and latency. Start the server first:
//   rheo haptic-server --scenario press_sphere --socket /tmp/haptic.sock &
//   rheo_haptic_example --socket /tmp/haptic.sock
// The path goes from --start down by --depth-mm and back (half the steps each way).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "host/haptic/haptic_link.hpp"
#include "sim/error.hpp"

int main(int argc, char** argv) {
  CLI::App app("Moves a sphere into clay and back through rheo haptic-server; reports rate and latency.");
  std::string socket = "/tmp/rheo-haptic.sock";
  int steps = 2000;
  double depth_mm = 12.0, rate_hz = 0.0;
  std::vector<double> start = {0.03, 0.03, 0.046};  // above press_sphere's dough
  app.add_option("--socket", socket, "the server's socket")->capture_default_str();
  app.add_option("--steps", steps, "steps in all (down, then up)")->check(CLI::Range(2, 100000000))->capture_default_str();
  app.add_option("--depth-mm", depth_mm, "how far the sphere goes down [mm]")->capture_default_str();
  app.add_option("--rate", rate_hz, "steps per second to hold (0: as fast as the loop goes)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--start", start, "the sphere's first position x,y,z [m]")->delimiter(',')->expected(3);
  CLI11_PARSE(app, argc, argv);
  try {
    rheo::haptic::HapticClient client(socket, std::chrono::milliseconds(10000));
    if (client.tools() != 1) {
      std::fprintf(stderr, "the server's scene has %zu tools; this example moves one\n", client.tools());
      return 1;
    }
    using Clock = std::chrono::steady_clock;
    std::vector<double> round_trip_us, compute_us;
    double peak_N = 0.0, peak_at_mm = 0.0;
    int late = 0;
    const auto begin = Clock::now();
    for (int i = 1; i <= steps; ++i) {
      // Down for the first half, back up for the second.
      const double s = i <= steps / 2 ? double(i) / (steps / 2) : double(steps - i) / (steps - steps / 2);
      rheo::ToolPose pose;
      pose.position = rheo::Vec3(start[0], start[1], start[2] - s * depth_mm * 1e-3);
      if (rate_hz > 0.0) {
        const auto due = begin + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>((i - 1) / rate_hz));
        if (Clock::now() > due + std::chrono::duration<double>(1.0 / rate_hz)) ++late;
        std::this_thread::sleep_until(due);
      }
      const auto t0 = Clock::now();
      const rheo::haptic::StepResult r = client.step({&pose, 1});
      round_trip_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      compute_us.push_back(r.server_compute_s * 1e6);
      const double f = r.reactions[0].force.norm();
      if (f > peak_N) peak_N = f, peak_at_mm = s * depth_mm;
    }
    const double wall = std::chrono::duration<double>(Clock::now() - begin).count();
    client.close();
    auto quantile = [](std::vector<double> v, double q) {
      std::sort(v.begin(), v.end());
      return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
    };
    const double p50 = quantile(round_trip_us, 0.5), p99 = quantile(round_trip_us, 0.99);
    std::printf("haptic example: %d steps of %.3g s simulated, sphere down %.3g mm and back\n",
                steps, client.dt(), depth_mm);
    std::printf("  rate:        %.0f steps/s achieved%s\n", steps / wall,
                rate_hz > 0 ? (" (asked " + std::to_string(static_cast<long>(rate_hz)) + ", " +
                               std::to_string(late) + " steps late)").c_str()
                            : " (as fast as the loop goes)");
    std::printf("  round trip:  median %.1f us, 99th percentile %.1f us, max %.1f us\n", p50, p99,
                quantile(round_trip_us, 1.0));
    std::printf("  server step: median %.1f us (the model's computation)\n", quantile(compute_us, 0.5));
    std::printf("  highest stable rate: %.0f steps/s (1 / the 99th-percentile round trip)\n", 1e6 / p99);
    std::printf("  largest reaction on the sphere: %.4g N at %.3g mm down\n", peak_N, peak_at_mm);
  } catch (const rheo::Error& e) {
    std::fprintf(stderr, "rheo_haptic_example: %s\n", e.what());
    return 1;
  }
  return 0;
}
