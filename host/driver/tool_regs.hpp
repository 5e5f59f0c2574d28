// The tool unit's registers (hls::ToolRegs, rtl/rheo_tool.sv) for one step of a model's
// rigid tool, in the units and formats of a core image. The hardware computes plane, sphere
// and cylinder contact with Coulomb friction (a turning cylinder's surface included);
// tool_hardware_gap says what a tool needs beyond it.
#pragma once

#include <string>

#include "hls/tool_contact.hpp"
#include "host/driver/core_image.hpp"
#include "sim/tool.hpp"

namespace rheo::driver {

// Why the tool unit cannot compute `tool` ("" when it can): a gripper.
std::string tool_hardware_gap(const Tool& tool);

// The registers of `tool` for the step that moves it from `before` to `now`:
//   c = now.position (X), dc = now.position - before.position (P: displacement per step),
//   a = the unit normal / axis (Q1.(B-2)), reach = eps (plane) or radius + eps,
//   half_length = length / 2 (cylinder), kt = k Lu / Fu, ct = c Lu / (dt Fu), mu, and for a
//   cylinder spin = (now.q - before.q) radius / Lu in P-format LSBs (its surface's
//   displacement over the step).
// Throws rheo::Error naming the tool (index) and the value that does not fit, and for a
// tool the unit does not compute (tool_hardware_gap).
hls::ToolRegs encode_tool(const Tool& tool, int index, const ToolPose& before,
                          const ToolPose& now, const CoreImage& image);

}  // namespace rheo::driver
