// The sample rate of the hidden-effect tests' virtual experiments (both generators).
//
// The default suite (label e2e) samples at 10 Hz; the same cases at the 20 Hz of the shipped
// data and of a typical texture analyser are the `long` executables
// (identify_*hidden_effect_long_test, tests/identify/CMakeLists.txt), built from the same
// sources with RHEO_HIDDEN_EFFECT_FULL_RATE. The protocol, the bodies, the noise and the
// assertions are the same; the object model steps a fixed number of times per sample
// interval (host/identify/object_specimen.hpp), so half the samples halve a diagnosis's
// simulation time. docs/testing.md ("The opt-in label long") has both.
#pragma once

namespace rheo::testing {

#ifdef RHEO_HIDDEN_EFFECT_FULL_RATE
inline constexpr double kHiddenEffectRateHz = 20.0;
#define RHEO_HIDDEN_EFFECT_SUITE EveryCauseFullRate
#else
inline constexpr double kHiddenEffectRateHz = 10.0;
#define RHEO_HIDDEN_EFFECT_SUITE EveryCause
#endif

}  // namespace rheo::testing
