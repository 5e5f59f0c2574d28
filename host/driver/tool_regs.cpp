#include "host/driver/tool_regs.hpp"

#include <cmath>

#include "sim/error.hpp"

namespace rheo::driver {
namespace {

std::int64_t word(double scaled, int width, const std::string& what) {
  const double limit = std::ldexp(1.0, width - 1);
  if (!std::isfinite(scaled) || std::fabs(scaled) >= limit - 1) {
    throw Error(what + " = " + std::to_string(scaled) + " LSB does not fit a " +
                std::to_string(width) + "-bit word");
  }
  return static_cast<std::int64_t>(std::llround(scaled));
}

}  // namespace

std::string tool_hardware_gap(const Tool& tool) {
  if (tool.shape == ToolShape::kGripper) return "a gripper (the tool unit has plane, sphere and cylinder)";
  return "";
}

hls::ToolRegs encode_tool(const Tool& tool, int index, const ToolPose& before,
                          const ToolPose& now, const CoreImage& image) {
  using Fmt = hls::HardwareFormat;
  using S = hls::CoefShifts<Fmt>;
  const std::string where = "tool " + std::to_string(index) + " (\"" + tool.name + "\")";
  const std::string gap = tool_hardware_gap(tool);
  if (!gap.empty()) throw Error(where + ": the hardware's tool unit does not compute " + gap);
  const double Lu = image.units.length_m, Fu = image.units.force_N, dt = image.units.dt_s;
  const int width = image.format.width;
  hls::ToolRegs t;
  switch (tool.shape) {
    case ToolShape::kPlane: t.kind = hls::kToolPlane; break;
    case ToolShape::kSphere: t.kind = hls::kToolSphere; break;
    case ToolShape::kCylinder: t.kind = hls::kToolCylinder; break;
    case ToolShape::kGripper: break;  // refused above
  }
  const char* axes = "xyz";
  const Vec3 a = tool.axis.normalized();
  for (int i = 0; i < 3; ++i) {
    t.c[i] = to_x_word(now.position[i], image, where + " position " + axes[i]);
    t.dc[i] = word(std::ldexp((now.position[i] - before.position[i]) / Lu, image.format.frac_p),
                   width, where + " displacement per step " + axes[i]);
    t.a[i] = std::llround(std::ldexp(a[i], Fmt::kFracU));
  }
  const double reach = tool.contact.eps + (tool.shape == ToolShape::kPlane ? 0.0 : tool.radius);
  t.reach = to_x_word(reach, image, where + " reach (radius + eps)");
  if (tool.shape == ToolShape::kCylinder) {
    t.half_length = to_x_word(0.5 * tool.length, image, where + " half length");
  }
  t.kt = encode_coef(tool.contact.k * Lu / Fu, where + " contact k", S::kKt);
  t.ct = encode_coef(tool.contact.c * Lu / (Fu * dt), where + " contact c / dt", S::kCt);
  t.mu = encode_coef(tool.contact.mu, where + " contact mu", S::kMu);
  if (tool.shape == ToolShape::kCylinder) {
    // The roller's surface moves by dq R along a x n over the step (sim/tool.cpp's v_surface).
    t.spin = encode_coef(std::ldexp((now.q - before.q) * tool.radius / Lu, image.format.frac_p),
                         where + " surface displacement per step (turn x radius)", S::kSpin);
  }
  return t;
}

}  // namespace rheo::driver
