#include "host/driver/bittrue_transport.hpp"

#include "host/driver/core_image.hpp"
#include "hls/frame_format.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

using Fmt = hls::HardwareFormat;

using hls::unpack_coef;

std::int64_t sword(std::uint32_t w) { return static_cast<std::int32_t>(w); }

constexpr int kOperandBits = Fmt::kOperandBits;

// The tool unit's registers as the RTL holds them: the kind in 2 bits, the normal or axis
// as operands (the word's low bits, sign-extended), the coefficients packed; an index
// beyond the registers is ignored.
void write_tool_register(hls::ToolRegs& t, std::uint32_t index, std::uint32_t w) {
  const auto operand = [](std::uint32_t v) {
    return static_cast<std::int64_t>(static_cast<std::int32_t>(v << (32 - kOperandBits)) >>
                                     (32 - kOperandBits));
  };
  switch (index) {
    case frame::kToolKind: t.kind = w & 3u; break;
    case frame::kToolCx: case frame::kToolCy: case frame::kToolCz:
      t.c[index - frame::kToolCx] = sword(w);
      break;
    case frame::kToolDcx: case frame::kToolDcy: case frame::kToolDcz:
      t.dc[index - frame::kToolDcx] = sword(w);
      break;
    case frame::kToolAx: case frame::kToolAy: case frame::kToolAz:
      t.a[index - frame::kToolAx] = operand(w);
      break;
    case frame::kToolReach: t.reach = sword(w); break;
    case frame::kToolHalfLength: t.half_length = sword(w); break;
    case frame::kToolKt: t.kt = unpack_coef(w); break;
    case frame::kToolCt: t.ct = unpack_coef(w); break;
    case frame::kToolMu: t.mu = unpack_coef(w); break;
    case frame::kToolSpin: t.spin = unpack_coef(w); break;
    default: break;
  }
}

std::uint32_t read_tool_register(const hls::ToolRegs& t, std::uint32_t index) {
  const auto word = [](std::int64_t v) { return static_cast<std::uint32_t>(v); };
  switch (index) {
    case frame::kToolKind: return t.kind;
    case frame::kToolCx: case frame::kToolCy: case frame::kToolCz:
      return word(t.c[index - frame::kToolCx]);
    case frame::kToolDcx: case frame::kToolDcy: case frame::kToolDcz:
      return word(t.dc[index - frame::kToolDcx]);
    case frame::kToolAx: case frame::kToolAy: case frame::kToolAz:
      return word(t.a[index - frame::kToolAx]);
    case frame::kToolReach: return word(t.reach);
    case frame::kToolHalfLength: return word(t.half_length);
    case frame::kToolKt: return hls::pack_coef(t.kt);
    case frame::kToolCt: return hls::pack_coef(t.ct);
    case frame::kToolMu: return hls::pack_coef(t.mu);
    case frame::kToolSpin: return hls::pack_coef(t.spin);
    default: return 0;
  }
}

}  // namespace

BitTrueTransport::BitTrueTransport(int lanes, const hls::EdgeElement& element)
    : lanes_(lanes), element_(element), mem_(std::make_unique<hls::CoreMemory>()) {
  mem_->lanes = lanes;
}

void BitTrueTransport::send(const std::vector<std::uint32_t>& words) {
  in_.insert(in_.end(), words.begin(), words.end());
  process();
}

std::vector<std::uint32_t> BitTrueTransport::receive(std::size_t n) {
  if (out_.size() < n) {
    throw Error(name() + ": expected " + std::to_string(n) + " response words, have " +
                std::to_string(out_.size()));
  }
  std::vector<std::uint32_t> got(out_.begin(), out_.begin() + n);
  out_.erase(out_.begin(), out_.begin() + n);
  return got;
}

void BitTrueTransport::write_word(std::uint32_t region, std::uint32_t index, std::uint32_t field,
                                  std::uint32_t w) {
  hls::CoreMemory& m = *mem_;
  switch (region) {
    case frame::kRegionGlobals:
      switch (index) {
        // Counts beyond the memories are refused, as the RTL core does.
        case frame::kGlobalNumParticles:
          if ((w & 0xFFFFFF) > std::uint32_t(hls::kMaxParticles))
            m.status |= hls::kStatusBadCommand;
          else
            m.num_particles = w & 0xFFFFFF;
          break;
        case frame::kGlobalEdgeRows:
          if ((w & 0xFFFFFF) * std::uint64_t(lanes_) > std::uint64_t(hls::kMaxEdges))
            m.status |= hls::kStatusBadCommand;
          else
            m.edge_rows = w & 0xFFFFFF;
          break;
        case frame::kGlobalGravityX:
          m.globals.g[0] = sword(w);
          break;
        case frame::kGlobalGravityY:
          m.globals.g[1] = sword(w);
          break;
        case frame::kGlobalGravityZ:
          m.globals.g[2] = sword(w);
          break;
        case frame::kGlobalControl:
          hls::write_control(m.globals, w & frame::kControlFloor, w & frame::kControlPlate,
                             w & frame::kControlPlateHold);
          break;
        default:
          m.status |= hls::kStatusBadCommand;
      }
      return;
    case frame::kRegionParticleState:
      if (index >= std::uint32_t(hls::kMaxParticles)) return;
      if (field < 3)
        m.particles[index].x[field] = sword(w);
      else
        m.particles[index].p[field - 3] = sword(w);
      return;
    case frame::kRegionParticleStatic:
      if (index >= std::uint32_t(hls::kMaxParticles)) return;
      if (field < 3)
        m.particles[index].x0[field] = sword(w);
      else if (field == 3)
        m.particles[index].minv = unpack_coef(w);
      else
        m.particles[index].flags = w & 3u;
      return;
    case frame::kRegionEdge: {
      if (index >= std::uint32_t(hls::kMaxEdges)) return;
      hls::EdgeEntry& e = m.edges[index];
      if (field == 0) {
        constexpr std::uint32_t kLocalMask = (1u << frame::kEdgeLocalBits) - 1;
        e.valid = w & frame::kEdgeValid;
        e.element = w & frame::kEdgeElement;
        e.second = w & frame::kEdgeSecond;
        e.s_local = w & kLocalMask;
        e.e_local = (w >> frame::kEdgeEndLocalShift) & kLocalMask;
        e.e_bank = (w >> frame::kEdgeEndBankShift) & ((1u << frame::kEdgeBankBits) - 1);
      } else if (field == 1) {
        e.L = sword(w);
      } else if (field == 2) {
        e.d = sword(w);
      } else {
        e.material = w & (hls::kMaxMaterials - 1);
      }
      return;
    }
    case frame::kRegionMaterial: {
      if (index >= std::uint32_t(hls::kMaxMaterials)) return;
      hls::MaterialCoefs& mc = m.materials[index];
      hls::Coef* coefs[6] = {&mc.alpha, &mc.beta, &mc.kt, &mc.ct, &mc.a_min, &mc.a_max};
      if (field < 6)
        *coefs[field] = unpack_coef(w);
      else
        mc.flags = w & 3u;
      return;
    }
    case frame::kRegionEdgeLength:
      if (index < std::uint32_t(hls::kMaxEdges)) m.edges[index].d = sword(w);
      return;
    case frame::kRegionMaterialDamper: {
      if (index >= std::uint32_t(hls::kMaxMaterials)) return;
      hls::MaterialCoefs& mc = m.materials[index];
      hls::Coef* coefs[frame::kDamperCoefs] = {&mc.d_lo,   &mc.d_span, &mc.zk,
                                               &mc.s_base, &mc.s_c2,   &mc.ka};
      if (field < frame::kDamperCoefs) *coefs[field] = unpack_coef(w);
      return;
    }
    case frame::kRegionMaterialHardening: {
      if (index >= std::uint32_t(hls::kMaxMaterials)) return;
      hls::MaterialCoefs& mc = m.materials[index];
      hls::Coef* coefs[frame::kHardeningCoefs] = {&mc.hk, &mc.s_k, &mc.ct_h};
      if (field < frame::kHardeningCoefs) *coefs[field] = unpack_coef(w);
      return;
    }
    case frame::kRegionTool:
      write_tool_register(m.tool, index, w);
      return;
    case frame::kRegionToolReaction:
      return;  // read only
    default: {
      // Maxwell arm j: its coefficients per material, its extension per edge slot.
      const int arm = frame::arm_of_region(region);
      if (arm < 0) return;
      if (frame::is_material_arm_region(region) && index < std::uint32_t(hls::kMaxMaterials)) {
        hls::MaterialCoefs& mc = m.materials[index];
        (field == 0 ? mc.gamma[arm] : mc.k2t[arm]) = unpack_coef(w);
      } else if (frame::is_edge_arm_region(region) && index < std::uint32_t(hls::kMaxEdges)) {
        m.edges[index].m[arm] = sword(w);
      }
      return;
    }
  }
}

std::uint32_t BitTrueTransport::read_word(std::uint32_t region, std::uint32_t index,
                                          std::uint32_t field) const {
  const hls::CoreMemory& m = *mem_;
  if (region == frame::kRegionParticleState && index < std::uint32_t(hls::kMaxParticles)) {
    const auto& q = m.particles[index];
    return static_cast<std::uint32_t>(field < 3 ? q.x[field] : q.p[field - 3]);
  }
  if (region == frame::kRegionEdgeLength && index < std::uint32_t(hls::kMaxEdges)) {
    return static_cast<std::uint32_t>(m.edges[index].d);
  }
  if (frame::is_edge_arm_region(region) && index < std::uint32_t(hls::kMaxEdges)) {
    return static_cast<std::uint32_t>(m.edges[index].m[frame::arm_of_region(region)]);
  }
  if (region == frame::kRegionTool) return read_tool_register(m.tool, index);
  if (region == frame::kRegionToolReaction && index < frame::kToolReactionWords) {
    return static_cast<std::uint32_t>(m.tool_reaction[index]);
  }
  return 0;
}

// Interprets every complete command at the front of the input (a RUN consumes its plate
// words as they arrive, one step per word).
void BitTrueTransport::process() {
  hls::CoreMemory& m = *mem_;
  while (!in_.empty()) {
    const std::uint32_t h = in_.front();
    const std::uint32_t op = frame::header_opcode(h);
    const std::uint32_t region = frame::header_region(h);
    const std::uint32_t count = frame::header_count(h);
    if (op == frame::kOpWrite || op == frame::kOpRead) {
      if (region >= frame::kNumRegions || !element_.accepts_region(region)) {
        m.status |= hls::kStatusBadCommand;
        in_.pop_front();
        continue;
      }
      const std::uint32_t wpe = frame::kWordsPerEntry[region];
      const std::size_t need = 2 + (op == frame::kOpWrite ? std::size_t(count) * wpe : 0);
      if (in_.size() < need) return;
      in_.pop_front();
      const std::uint32_t first = in_.front();
      in_.pop_front();
      for (std::uint32_t n = 0; n < count; ++n) {
        for (std::uint32_t f = 0; f < wpe; ++f) {
          if (op == frame::kOpWrite) {
            write_word(region, first + n, f, in_.front());
            in_.pop_front();
          } else {
            out_.push_back(read_word(region, first + n, f));
          }
        }
      }
    } else if (op == frame::kOpRun) {
      if (count == 0) {
        in_.pop_front();
        continue;
      }
      if (in_.size() < 2) return;
      // Step with the next plate word; the header stays with the remaining count.
      in_.pop_front();
      hls::start_step(m.globals, sword(in_.front()));
      in_.pop_front();
      const std::int64_t plate_force = hls::core_step_for<Fmt>(element_, m);
      out_.push_back(static_cast<std::uint32_t>(plate_force));
      cycles_ += static_cast<std::uint32_t>(
          cycles_per_step_formula(int(m.edge_rows), int(m.num_particles), lanes_, element_));
      if (count > 1) in_.push_front(frame::header(frame::kOpRun, frame::kRegionGlobals, count - 1));
    } else if (op == frame::kOpStatus) {
      in_.pop_front();
      out_.push_back(m.status);
      out_.push_back(m.step_count);
      out_.push_back(cycles_);
      out_.push_back(static_cast<std::uint32_t>(lanes_));
      if (count & frame::kStatusClear) m.status = 0;
    } else {
      m.status |= hls::kStatusBadCommand;
      in_.pop_front();
    }
  }
}

}  // namespace rheo::driver
