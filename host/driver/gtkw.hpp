// GTKWave save files for the RTL core's FST waveforms, generated from the signals that
// are really in the FST (so a renamed or resized RTL signal is an error here, not a trace
// GTKWave drops without a word), and the fixed-point -> physical-unit translation that
// GTKWave's process filter (`rheo-gtkw-filter`) applies to the state words.
//
// Which signals are shown, how and under which name is the table kTraceGroups in
// gtkw.cpp: the one place to edit when the RTL changes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "host/driver/core_image.hpp"

namespace rheo::driver {

// A fixed-point word shown in a physical unit: value = word * 2^-frac * scale, the word
// `width` bits two's complement.
struct FixedScale {
  int width = 32;
  int frac = 0;
  double scale = 1.0;
  std::string unit;
};

// The scales of the three state-word kinds for one unit choice: positions (X format) in
// mm, displacements per step (P format) as velocities in m/s, forces (F format) in N.
// `width` is the word width; accumulators pass their own.
FixedScale position_scale(const FormatDesc& format, const Units& units, int width);
FixedScale velocity_scale(const FormatDesc& format, const Units& units, int width);
FixedScale force_scale(const FormatDesc& format, const Units& units, int width);

// The filter's command-line arguments ("--width 32 --frac 27 --scale 5.0 --unit mm") and
// back. GTKWave hands everything after the program name over as ONE argument, so the
// parser splits on white space itself. Throws rheo::Error on anything else.
std::string filter_args(const FixedScale& scale);
FixedScale parse_filter_args(const std::string& args);

// One value as GTKWave passes it to a process filter (the trace's hex digits, one line)
// -> its physical value, e.g. "12.5 mm". Text that is not a hex number (x, z, empty) is
// returned as it is.
std::string translate_word(const FixedScale& scale, std::string_view hex);

// A signal of an FST as GTKWave names it: scopes joined by '.', then the variable name
// with its bit range, e.g. "rheo_core.rheo_core.g_lane[0].u_tem.f_o[95:0]".
struct FstSignal {
  std::string path;
  int width = 1;
};

// A traced step (or batch of steps): FST times of its first clock and of the clock after
// its last force word left the core.
struct TracedSteps {
  long first_step = 1;
  long steps = 1;
  std::uint64_t start_time = 0;
  std::uint64_t end_time = 0;
};

struct GtkwOptions {
  std::string core_scope = "rheo_core.rheo_core";  // the core's instance in the FST
  bool sweep = false;  // the sweep core (rtl/rheo_sweep_core.sv in rtl/rheo_sweep_tb.sv)
  int lanes = 1;
  int maxwell_arms = 0;            // Maxwell arms of the core's edge element: their m words
  FormatDesc format;               // binary points of the state words (the RTL's: HardwareFormat)
  Units units;                     // the model's unit choice (CoreImage::units)
  std::string filter_command;      // absolute path of rheo-gtkw-filter (no white space)
  std::vector<TracedSteps> steps;  // at least the first; the view opens on steps[0]
  std::string dump_file;           // written as [dumpfile] when not empty
  int window_width = 1600;         // [size] of the GTKWave window, pixels
  int window_height = 900;
  int signals_width = 330;  // width of the signal-name pane, pixels
};

// The save file for an FST holding `signals`. Throws rheo::Error naming every listed
// signal that is missing from `signals` or has an unexpected width, and on duplicate
// trace names.
std::string make_gtkw(const std::vector<FstSignal>& signals, const GtkwOptions& options);

// GTKWave's zoom value for `time_units` of time across `pixels`: GTKWave draws 2^-zoom
// time units per 200 pixels (calczoom in its wavewindow.c).
double gtkw_zoom(double time_units, double pixels);

}  // namespace rheo::driver
