// The edge element a core computes: which optional parts of the three-element edge its TEMs
// carry. One descriptor is read by everything that depends on the variant, so that a new
// variant is one table entry here plus its arithmetic, not a flag passed through every layer:
//   - the bit-true model (core_step_for picks the kernel instantiation),
//   - the host's core image (which coefficients and edge words it encodes, which of the
//     model's features it keeps: host/driver/core_image.hpp),
//   - the frame format (which regions the core accepts),
//   - the RTL (rtl_parameters: the elaboration parameters of rheo_core / rheo_tem that build
//     the variant, for Verilator's -G and Yosys' chparam),
//   - the transports and backends that choose a core for a model.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "hls/frame_format.hpp"
#include "hls/rheo_kernel.hpp"

namespace rheo::hls {

// One elaboration parameter of the RTL core (name as in rtl/rheo_core.sv).
struct RtlParameter {
  std::string_view name;
  int value = 0;
  bool tem = true;  // rheo_tem takes it too (false: a parameter of rheo_core only)
};

struct EdgeElement {
  std::string_view name;  // as the command line and the reports spell it
  std::string_view description;
  // Parallel Maxwell arms per edge (each a spring in series with a damper, with its own
  // extension state), 0..kMaxArms.
  int maxwell_arms = 0;
  // Force-dependent series damper (seed 000 §3.3): the series damper's viscosity falls with
  // the Voigt spring force (hls::damper_coefs).
  bool series_damper = false;
  // Strain hardening: the Voigt spring stiffens with the edge's strain
  // (hls::hardened_coefs). Its TEM runs kHardTemExtra clocks longer.
  bool strain_hardening = false;
  // Volume (3-D) preservation: the core's edge pass also computes volume elements, one per
  // two slots of a lane (hls::volume_element). Not a part of the edge, but of the core
  // that carries it, so it is named with the edge element.
  bool volume_preservation = false;
  // The tool unit: per lane, each particle's contact with one rigid tool (plane, sphere or
  // cylinder; penalty force with Coulomb friction) in the MPM pass (hls/tool_contact.hpp). A
  // part of the core, like the volume unit. Its MPM pass runs kToolLatency clocks longer.
  bool tool_contact = false;

  constexpr bool has_maxwell_arm() const { return maxwell_arms > 0; }
  // Whether the edge's coefficients are scaled per edge (the damper or hardening): the arms'
  // lead on ldot is then a coefficient of its own (ka) rather than part of ct.
  constexpr bool scales_coefficients() const { return series_damper || strain_hardening; }
  // Clocks from the last edge row until its force sums land (the cycle formula's TemDrain).
  constexpr int tem_drain_cycles() const {
    return hls::tem_drain_cycles(strain_hardening, series_damper);
  }
  // Clocks from the last particle row until its state is written (the cycle formula's
  // MpmDrain): the tool unit and its sum stage sit in front of the MPM.
  constexpr int mpm_drain_cycles() const {
    return kMpmDrainCycles + (tool_contact ? kToolLatency + 1 : 0);
  }
  // Packed coefficients per material the TEM reads (region Material, the damper's, then
  // the arms').
  constexpr int material_coefficients() const {
    return 6 + (series_damper ? int(frame::kDamperCoefs) : 0) +
           (strain_hardening ? int(frame::kHardeningCoefs) : 0) + 2 * maxwell_arms;
  }
  // Whether the core accepts a write or read of `region` (the base regions, a region pair
  // per arm, the damper's region); any other region is a bad command.
  constexpr bool accepts_region(std::uint32_t region) const {
    if (region < frame::kNumBaseRegions) return true;
    if (region == frame::kRegionMaterialDamper) return series_damper;
    if (region == frame::kRegionMaterialHardening) return strain_hardening;
    if (region == frame::kRegionTool || region == frame::kRegionToolReaction) return tool_contact;
    return frame::arm_of_region(region) >= 0 && frame::arm_of_region(region) < maxwell_arms;
  }
  // The RTL parameters that build this variant (beside Lanes).
  constexpr std::array<RtlParameter, 5> rtl_parameters() const {
    return {RtlParameter{"MaxwellArms", maxwell_arms},
            RtlParameter{"SeriesDamper", series_damper ? 1 : 0},
            RtlParameter{"StrainHardening", strain_hardening ? 1 : 0},
            RtlParameter{"VolumePreservation", volume_preservation ? 1 : 0, false},
            RtlParameter{"ToolContact", tool_contact ? 1 : 0, false}};
  }
  friend constexpr bool operator==(const EdgeElement& a, const EdgeElement& b) {
    return a.maxwell_arms == b.maxwell_arms && a.series_damper == b.series_damper &&
           a.strain_hardening == b.strain_hardening &&
           a.volume_preservation == b.volume_preservation && a.tool_contact == b.tool_contact;
  }
};

inline constexpr EdgeElement kThreeElement{
    "three-element", "Voigt spring+damper in series with a damper (the paper's TEM)", 0};
inline constexpr EdgeElement kThreeElementWithArm{
    "three-element+arm",
    "the three-element edge with a parallel Maxwell arm (a second relaxation time)", 1};
inline constexpr EdgeElement kThreeElementWith4Arms{
    "three-element+4arms",
    "the three-element edge with four parallel Maxwell arms (a relaxation spectrum)", 4};
inline constexpr EdgeElement kThreeElementWith8Arms{
    "three-element+8arms",
    "the three-element edge with eight parallel Maxwell arms (the diagnosis' power-law "
    "relaxation spectrum)",
    8};
static_assert(kThreeElementWith8Arms.maxwell_arms == kMaxArms);
inline constexpr EdgeElement kThreeElementWithDamper{
    "three-element+damper",
    "the three-element edge with the force-dependent series damper (seed 000 §3.3)", 0, true};
inline constexpr EdgeElement kThreeElementWithDamper8Arms{
    "three-element+damper+8arms",
    "the three-element edge with the force-dependent series damper and eight parallel "
    "Maxwell arms",
    8, true};
inline constexpr EdgeElement kThreeElementWithHardening{
    "three-element+hardening",
    "the three-element edge with strain hardening (the Voigt spring stiffens with the strain)",
    0, false, true};
// Every edge effect at once: the damper's state then follows the hardened spring's force
// (rtl/rheo_harden.sv runs the damper after h). Hardening with arms needs this element:
// the arms' lead on ldot (ka) is one of the damper's coefficients.
inline constexpr EdgeElement kThreeElementEveryEffect{
    "three-element+damper+hardening+8arms",
    "the three-element edge with every effect: the force-dependent series damper, strain "
    "hardening and eight parallel Maxwell arms",
    8, true, true};

// Volume preservation beside the paper's edge, and beside every edge effect (the core of a
// model with every feature).
inline constexpr EdgeElement kThreeElementWithVolume{
    "three-element+volume",
    "the three-element edge, and volume-preserving forces per tetrahedron in the edge pass", 0,
    false, false, true};
inline constexpr EdgeElement kEveryFeature{
    "three-element+damper+hardening+8arms+volume",
    "every feature: the edge with every effect, and volume-preserving forces per tetrahedron",
    8, true, true, true};

// The paper's edge in a core with the tool unit (a rigid tool pressed into the object).
inline constexpr EdgeElement kThreeElementWithTool{
    "three-element+tool",
    "the three-element edge, and a tool unit per lane: each particle's penalty contact with "
    "a rigid plane, sphere or cylinder in the MPM pass",
    0, false, false, false, true};

// Every variant the bit-true model and the RTL implement, in the order edge_element_with
// tries them (among variants with the same parts, fewer arms first).
inline constexpr std::array<EdgeElement, 11> kEdgeElements{
    kThreeElement,           kThreeElementWithArm,    kThreeElementWith4Arms,
    kThreeElementWith8Arms,  kThreeElementWithDamper, kThreeElementWithDamper8Arms,
    kThreeElementWithHardening, kThreeElementEveryEffect, kThreeElementWithVolume,
    kEveryFeature,           kThreeElementWithTool};

// The variant named `name`, or nullptr.
constexpr const EdgeElement* find_edge_element(std::string_view name) {
  for (const EdgeElement& e : kEdgeElements) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

// The simplest variant with at least `arms` Maxwell arms (and the series damper when
// `damper`, strain hardening when `hardening`, volume preservation when `volume`, the tool
// unit when `tool`), or nullptr. A variant with the tool unit is chosen only for a tool.
constexpr const EdgeElement* edge_element_with(int arms, bool damper, bool hardening = false,
                                               bool volume = false, bool tool = false) {
  for (const EdgeElement& e : kEdgeElements) {
    if (e.maxwell_arms >= arms && (e.series_damper || !damper) &&
        (e.strain_hardening || !hardening) && (e.volume_preservation || !volume) &&
        e.tool_contact == tool)
      return &e;
  }
  return nullptr;
}

namespace detail {
template <class Fmt, std::size_t... I>
inline std::int64_t core_step_for(const EdgeElement& element, CoreMemory& mem,
                                  std::index_sequence<I...>) {
  std::int64_t plate = 0;
  // Exactly one variant is the element (the variants are unique); the fold stops at it.
  const bool stepped =
      ((element == kEdgeElements[I]
            ? (plate = core_step<Fmt, kEdgeElements[I].maxwell_arms,
                                 kEdgeElements[I].series_damper,
                                 kEdgeElements[I].strain_hardening,
                                 kEdgeElements[I].volume_preservation,
                                 kEdgeElements[I].tool_contact>(mem),
               true)
            : false) ||
       ...);
  if (!stepped) mem.status |= kStatusBadCommand;  // an element no core is built for
  return plate;
}
}  // namespace detail

// One step of the core built for `element` (the kernel instantiation of that variant).
template <class Fmt>
inline std::int64_t core_step_for(const EdgeElement& element, CoreMemory& mem) {
  return detail::core_step_for<Fmt>(element, mem, std::make_index_sequence<kEdgeElements.size()>{});
}

}  // namespace rheo::hls
