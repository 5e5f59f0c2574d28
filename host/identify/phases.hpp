// Protocol phases of a measurement (push, hold, release, after release) and the residual
// summaries the diagnosis and the causes' explanations read per phase.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "host/identify/measurement.hpp"

namespace rheo::identify {

// Plate movements below this per sample [mm] count as standing still.
inline constexpr double kStillMm = 1e-6;

enum class Phase { kPush, kHold, kRelease, kAfterRelease };
std::string phase_name(Phase p);
// Phase of every sample from the plate history: push (plate moving down, or at rest before
// the first push), hold (plate still and down), release (plate moving up), after release
// (plate back at 0 after a push).
std::vector<Phase> phases_of(const Measurement& m);

// The samples of one phase, in order.
std::vector<std::size_t> indices_of(const std::vector<Phase>& ph, Phase p);
// Mean of r over the samples idx[a .. b) (0 when empty).
double mean_of(const std::vector<double>& r, const std::vector<std::size_t>& idx, std::size_t a,
               std::size_t b);

}  // namespace rheo::identify
