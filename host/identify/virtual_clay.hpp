// Seed 002's clay experiment as a virtual experiment: the two push-hold-release protocols
// and the identified four-element parameters (Table II, model b) mapped onto the column's
// three-element edge plus its parallel Maxwell arm.
#pragma once

#include <cstdint>

#include "host/identify/measurement.hpp"
#include "host/identify/specimen.hpp"
#include "sim/four_element.hpp"

namespace rheo::identify {

// Seed 002, Table II (model b): identified four-element parameters.
struct FourElementB {
  double E1 = 5.8388e4;  // [Pa]
  double E2 = 1.2353e5;  // [Pa]
  double c1 = 2.1091e7;  // [Pa s]
  double c2 = 8.3402e5;  // [Pa s]
};

// Model (b)'s relaxation modulus (sim/four_element.hpp): G(t) = 83.19 kPa e^(-t/4.566 s) +
// 40.34 kPa e^(-t/534.1 s) for Table II. The slow arm goes to the three-element edge
// (E1 = g_slow, c1 + c2 = g_slow tau_slow, with a small Voigt viscosity c1 = voigt_share
// (c1 + c2) that only sets how fast the elastic recovery after release is), the fast arm to
// the parallel Maxwell arm (E2 = g_fast, c3 = g_fast tau_fast).
RelaxationArms relaxation_arms(const FourElementB& b);
SpecimenParams clay_column_params(const FourElementB& b, double voigt_share = 1e-3);

// Plate history sampled at `rate_hz`: push at push_speed to depth, hold, retract at
// release_speed to 0, then stay for after_s. force_N is zero and surface_mm empty.
Measurement push_hold_release(const Geometry& g, double depth_mm, double push_speed_mm_s,
                              double hold_s, double release_speed_mm_s, double after_s,
                              double rate_hz);

// Adds Gaussian load-cell noise (sigma_N) and quantisation (resolution_N) to force_N.
void add_load_cell_noise(Measurement& m, double sigma_N, double resolution_N, std::uint32_t seed);

}  // namespace rheo::identify
