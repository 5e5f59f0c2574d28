// The fixed-point -> physical-unit translation GTKWave shows through rheo-gtkw-filter:
// known words of each state-word kind, agreement with the host's own word conversions,
// the filter's argument syntax, and the filter process itself spoken to as GTKWave does
// (all arguments in one argv string, one value per line, one answer per line at once).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "hls/fixed_format.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/gtkw.hpp"
#include "sim/error.hpp"
#include "tests/test_paths.hpp"

namespace rheo::driver {
namespace {

// A unit choice like block5's: Lu = 5 mm, Fu = 0.2 N, dt = 1 ms.
const Units kUnits{0.005, 0.2, 0.001};
const FormatDesc kFormat = FormatDesc::of<hls::HardwareFormat>();
constexpr int kW = hls::HardwareFormat::kWidth;

std::string hex32(std::int64_t word) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08X", static_cast<unsigned>(static_cast<std::uint32_t>(word)));
  return buf;
}

std::string g6(double v, const char* unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g %s", v, unit);
  return buf;
}

TEST(GtkwFilter, KnownWordsInPhysicalUnits) {
  const FixedScale x = position_scale(kFormat, kUnits, kW);
  const FixedScale p = velocity_scale(kFormat, kUnits, kW);
  const FixedScale f = force_scale(kFormat, kUnits, kW);
  // One length unit, minus one and a half.
  EXPECT_EQ(translate_word(x, hex32(std::int64_t{1} << kFormat.frac_x)), "5 mm");
  EXPECT_EQ(translate_word(x, hex32(-(std::int64_t{3} << (kFormat.frac_x - 1)))), "-7.5 mm");
  // 2^-10 Lu per step = 2^-10 * 5 mm / 1 ms.
  EXPECT_EQ(translate_word(p, hex32(std::int64_t{1} << (kFormat.frac_p - 10))), "0.00488281 m/s");
  // Five force units = 1 N; the smallest negative step.
  EXPECT_EQ(translate_word(f, hex32(std::int64_t{5} << kFormat.frac_f)), "1 N");
  EXPECT_EQ(translate_word(f, "FFFFFFFF"), g6(-std::ldexp(0.2, -kFormat.frac_f), "N"));
  EXPECT_EQ(translate_word(f, "00000000"), "0 N");
  // The most negative and most positive words.
  EXPECT_EQ(translate_word(x, "80000000"), g6(-std::ldexp(5.0, kW - 1 - kFormat.frac_x), "mm"));
  EXPECT_EQ(translate_word(x, "7FFFFFFF"),
            g6(std::ldexp(5.0, kW - 1 - kFormat.frac_x) - std::ldexp(5.0, -kFormat.frac_x), "mm"));
}

TEST(GtkwFilter, WideAccumulatorKeepsTheBinaryPoint) {
  // A 48-bit plate-force accumulator: -1 force unit.
  const FixedScale f = force_scale(kFormat, kUnits, 48);
  EXPECT_EQ(translate_word(f, "FFFFFFF00000"), "-0.2 N");
  EXPECT_EQ(translate_word(f, "000000100000"), "0.2 N");
}

TEST(GtkwFilter, AgreesWithTheHostConversions) {
  CoreImage image;
  image.format = kFormat;
  image.units = kUnits;
  const FixedScale x = position_scale(kFormat, kUnits, kW);
  const FixedScale p = velocity_scale(kFormat, kUnits, kW);
  const FixedScale f = force_scale(kFormat, kUnits, kW);
  std::mt19937 rng(11);
  for (int i = 0; i < 1000; ++i) {
    const std::int32_t w = static_cast<std::int32_t>(rng());
    EXPECT_EQ(translate_word(x, hex32(w)), g6(from_x_word(w, image) * 1e3, "mm")) << w;
    EXPECT_EQ(translate_word(p, hex32(w)), g6(from_p_word(w, image), "m/s")) << w;
    EXPECT_EQ(translate_word(f, hex32(w)), g6(from_f_word(w, image), "N")) << w;
  }
}

TEST(GtkwFilter, LeavesNonNumbersAlone) {
  const FixedScale x = position_scale(kFormat, kUnits, kW);
  EXPECT_EQ(translate_word(x, "xxxxxxxx"), "xxxxxxxx");
  EXPECT_EQ(translate_word(x, "ZZZZZZZZ"), "ZZZZZZZZ");
  EXPECT_EQ(translate_word(x, ""), "");
  EXPECT_EQ(translate_word(x, "08000000\r"), "5 mm");  // line ends and case do not matter
  EXPECT_EQ(translate_word(x, " 0800000a "), translate_word(x, "0800000A"));
}

TEST(GtkwFilter, ArgumentsRoundTripAndBadOnesAreRefused) {
  const FixedScale v = velocity_scale(kFormat, kUnits, kW);
  const FixedScale back = parse_filter_args(filter_args(v));
  EXPECT_EQ(back.width, v.width);
  EXPECT_EQ(back.frac, v.frac);
  EXPECT_EQ(back.scale, v.scale);  // printed with 17 digits: exact
  EXPECT_EQ(back.unit, "m/s");
  EXPECT_THROW(parse_filter_args(""), Error);
  EXPECT_THROW(parse_filter_args("--width 32 --frac 27 --scale 5"), Error);
  EXPECT_THROW(parse_filter_args("--width 32 --frac 27 --scale 5x --unit mm"), Error);
  EXPECT_THROW(parse_filter_args("--width 65 --frac 27 --scale 5 --unit mm"), Error);
  EXPECT_THROW(parse_filter_args("--width 32 --frac 27 --scale 5 --unit mm --oops 1"), Error);
}

TEST(GtkwZoom, TimeAcrossThePaneMatchesGtkwave) {
  // GTKWave draws 2^-zoom time units per 200 pixels.
  EXPECT_DOUBLE_EQ(gtkw_zoom(1.0, 200.0), 0.0);
  EXPECT_DOUBLE_EQ(gtkw_zoom(1024.0, 200.0), -10.0);
  EXPECT_NEAR(std::exp2(-gtkw_zoom(1300.0, 1200.0)) * 1200.0 / 200.0, 1300.0, 1e-9);
}

// One line read from fd within `timeout_ms` (empty on timeout or end of file).
std::string read_line(int fd, int timeout_ms) {
  std::string line;
  char c;
  while (true) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) return line;
    if (read(fd, &c, 1) != 1) return line;
    if (c == '\n') return line;
    line += c;
  }
}

// The process as GTKWave runs it (pipeio.c: execl(path, path, args, NULL)): every value
// is answered before the next one is written, so a filter that buffered its output would
// hang GTKWave and fail here on the timeout.
TEST(GtkwFilterProcess, AnswersEachLineAtOnce) {
  int to_child[2], from_child[2];
  ASSERT_EQ(pipe(to_child), 0);
  ASSERT_EQ(pipe(from_child), 0);
  const std::string args = filter_args(position_scale(kFormat, kUnits, kW));
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    dup2(to_child[0], 0);
    dup2(from_child[1], 1);
    close(to_child[1]);
    close(from_child[0]);
    execl(RHEO_GTKW_FILTER, RHEO_GTKW_FILTER, args.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(to_child[0]);
  close(from_child[1]);
  const struct {
    const char* in;
    const char* out;
  } cases[] = {{"08000000", "5 mm"},
               {"F4000000", "-7.5 mm"},
               {"xxxxxxxx", "xxxxxxxx"},
               {"00000000", "0 mm"}};
  for (const auto& c : cases) {
    const std::string line = std::string(c.in) + "\n";
    ASSERT_EQ(write(to_child[1], line.data(), line.size()), ssize_t(line.size()));
    EXPECT_EQ(read_line(from_child[0], 5000), c.out) << c.in;
  }
  close(to_child[1]);
  int status = 0;
  waitpid(pid, &status, 0);
  close(from_child[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

}  // namespace
}  // namespace rheo::driver
