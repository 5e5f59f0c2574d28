#include "host/driver/device.hpp"

#include "hls/fixed_format.hpp"
#include "hls/frame_format.hpp"
#include "sim/error.hpp"

namespace rheo::driver {

std::string describe_status_flags(std::uint32_t flags) {
  static const std::pair<std::uint32_t, const char*> kNames[] = {
      {hls::kStatusTemSaturated, "TEM result saturated"},
      {hls::kStatusMpmSaturated, "MPM result saturated"},
      {hls::kStatusDegenerateEdge, "zero-length edge"},
      {hls::kStatusPlateSaturated, "plate force saturated"},
      {hls::kStatusBadCommand, "bad command"},
      {hls::kStatusScheduleConflict, "edge schedule conflict"},
      {hls::kStatusVolumeSaturated, "volume element force saturated"},
      {hls::kStatusToolReactionSaturated, "tool reaction force saturated"},
  };
  std::string out;
  for (const auto& [bit, name] : kNames) {
    if (flags & bit) out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out.empty() ? "none" : out;
}

Device::Device(std::unique_ptr<Transport> transport) : transport_(std::move(transport)) {}

void Device::load(const CoreImage& image) { load_frames(image_frames(image), image.lanes, false); }

void Device::load_frames(const std::vector<std::uint32_t>& frames, int lanes, bool sweep) {
  transport_->send(frames);
  const CoreStatus st = read_status(true);
  if (st.flags & hls::kStatusBadCommand) {
    throw Error(transport_->name() + ": the core rejected the model image (bad command)");
  }
  if (st.sweep != sweep) {
    throw Error(transport_->name() + ": image built for " +
                (sweep ? "the sweep core" : "rheo_core") + ", the core is " +
                (st.sweep ? "the sweep core" : "rheo_core"));
  }
  if (st.lanes != static_cast<std::uint32_t>(lanes)) {
    throw Error(transport_->name() + ": image built for " + std::to_string(lanes) +
                " lanes, core has " + std::to_string(st.lanes));
  }
}

std::vector<std::int32_t> Device::run(const std::vector<std::int32_t>& plate_words) {
  if (plate_words.empty()) return {};
  std::vector<std::uint32_t> words;
  words.reserve(plate_words.size() + 1);
  words.push_back(frame::header(frame::kOpRun, frame::kRegionGlobals,
                                static_cast<std::uint32_t>(plate_words.size())));
  for (std::int32_t w : plate_words) words.push_back(static_cast<std::uint32_t>(w));
  transport_->send(words);
  const std::vector<std::uint32_t> got = transport_->receive(plate_words.size());
  const CoreStatus st = read_status(false);
  if (st.flags != 0) {
    throw Error(transport_->name() + ": core overflow flags after step " +
                std::to_string(st.step_count) + ": " + describe_status_flags(st.flags) +
                " (the model leaves the fixed-point range; reduce dt or the load)");
  }
  return std::vector<std::int32_t>(got.begin(), got.end());
}

std::vector<std::int32_t> Device::read_region(std::uint32_t region, int first, int count) {
  if (count <= 0) return {};
  transport_->send({frame::header(frame::kOpRead, frame::Region(region), std::uint32_t(count)),
                    std::uint32_t(first)});
  const std::vector<std::uint32_t> got =
      transport_->receive(std::size_t(count) * frame::kWordsPerEntry[region]);
  return std::vector<std::int32_t>(got.begin(), got.end());
}

std::vector<std::int32_t> Device::read_particle_state(int first, int count) {
  return read_region(frame::kRegionParticleState, first, count);
}

std::vector<std::int32_t> Device::read_voigt_lengths(int first, int count) {
  return read_region(frame::kRegionEdgeLength, first, count);
}

std::vector<std::int32_t> Device::read_arm_extensions(int arm, int first, int count) {
  if (arm < 0 || arm >= frame::kMaxArms) {
    throw Error("Maxwell arm " + std::to_string(arm) + ": a core has arms 0.." +
                std::to_string(frame::kMaxArms - 1));
  }
  return read_region(frame::edge_arm_region(arm), first, count);
}

void Device::write_tool(const hls::ToolRegs& t) {
  const auto word = [](std::int64_t v) { return static_cast<std::uint32_t>(v); };
  std::vector<std::uint32_t> w = {
      frame::header(frame::kOpWrite, frame::kRegionTool, frame::kNumToolRegisters), 0u};
  w.resize(2 + frame::kNumToolRegisters);
  std::uint32_t* r = w.data() + 2;
  r[frame::kToolKind] = t.kind;
  for (int a = 0; a < 3; ++a) {
    r[frame::kToolCx + a] = word(t.c[a]);
    r[frame::kToolDcx + a] = word(t.dc[a]);
    r[frame::kToolAx + a] = word(t.a[a]);
  }
  r[frame::kToolReach] = word(t.reach);
  r[frame::kToolHalfLength] = word(t.half_length);
  r[frame::kToolKt] = hls::pack_coef(t.kt);
  r[frame::kToolCt] = hls::pack_coef(t.ct);
  r[frame::kToolMu] = hls::pack_coef(t.mu);
  r[frame::kToolSpin] = hls::pack_coef(t.spin);
  transport_->send(w);
}

std::array<std::int32_t, 3> Device::read_tool_reaction() {
  const std::vector<std::int32_t> w = read_region(frame::kRegionToolReaction, 0, 3);
  return {w[0], w[1], w[2]};
}

CoreStatus Device::read_status(bool clear) {
  transport_->send(
      {frame::header(frame::kOpStatus, frame::kRegionGlobals, clear ? frame::kStatusClear : 0u)});
  const std::vector<std::uint32_t> w = transport_->receive(frame::kStatusWords);
  return {w[0], w[1], w[2], w[3] & frame::kStatusLanesMask, (w[3] & frame::kStatusLanesSweep) != 0};
}

}  // namespace rheo::driver
