#include "host/driver/sweep_bittrue_transport.hpp"

#include "hls/frame_format.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

using Fmt = hls::HardwareFormat;

std::int64_t sword(std::uint32_t w) { return static_cast<std::int32_t>(w); }

bool particle_region(std::uint32_t r) {
  return r == frame::kRegionParticleState || r == frame::kRegionSweepParticle;
}
bool slot_region(std::uint32_t r) {
  return r == frame::kRegionSweepEdge || r == frame::kRegionEdgeLength;
}
// The regions the sweep core decodes (rtl/rheo_sweep_ctrl.sv, region_ok); EdgeLength is
// read-only there (a Voigt length is written with its tag, region SweepEdge).
bool region_ok(std::uint32_t r, bool write) {
  if (write && r == frame::kRegionEdgeLength) return false;
  return r == frame::kRegionGlobals || r == frame::kRegionParticleState ||
         r == frame::kRegionMaterial || r == frame::kRegionEdgeLength ||
         (r >= frame::kRegionSweepParticle && r <= frame::kRegionSweepMass);
}

}  // namespace

SweepBitTrueTransport::SweepBitTrueTransport(int lanes, int slab_depth, int ghost_depth)
    : lanes_(lanes),
      slab_depth_(slab_depth),
      ghost_depth_(ghost_depth),
      mem_(std::make_unique<hls::SweepMemory>()) {
  if (lanes < 1 || lanes > hls::kSweepMaxLanes || slab_depth > hls::kSweepSlabDepth ||
      ghost_depth > hls::kSweepGhostDepth)
    throw Error("sweep bit-true model: lanes 1.." + std::to_string(hls::kSweepMaxLanes) +
                ", memories at most the kernel's");
  mem_->lanes = std::uint32_t(lanes);
}

void SweepBitTrueTransport::send(const std::vector<std::uint32_t>& words) {
  in_.insert(in_.end(), words.begin(), words.end());
  process();
}

std::vector<std::uint32_t> SweepBitTrueTransport::receive(std::size_t n) {
  if (out_.size() < n) {
    throw Error(name() + ": expected " + std::to_string(n) + " response words, have " +
                std::to_string(out_.size()));
  }
  std::vector<std::uint32_t> got(out_.begin(), out_.begin() + n);
  out_.erase(out_.begin(), out_.begin() + n);
  return got;
}

bool SweepBitTrueTransport::locate(std::uint32_t index, std::uint32_t& lane,
                                   std::uint32_t& local) const {
  for (int j = lanes_ - 1; j >= 0; --j) {
    const hls::SweepLaneRegs& l = mem_->lane[j];
    if (l.count == 0 || index < l.first) continue;
    lane = std::uint32_t(j);
    local = index - l.first;
    return local < l.count;
  }
  return false;
}

void SweepBitTrueTransport::write_word(std::uint32_t region, std::uint32_t index,
                                       std::uint32_t field, std::uint32_t w) {
  hls::SweepMemory& m = *mem_;
  const std::uint32_t wpe = frame::kWordsPerEntry[region];
  switch (region) {
    case frame::kRegionGlobals:
      switch (index) {
        case frame::kGlobalNumParticles:
        case frame::kGlobalEdgeRows:
          break;
        case frame::kGlobalGravityX:
        case frame::kGlobalGravityY:
        case frame::kGlobalGravityZ:
          m.globals.g[index - frame::kGlobalGravityX] = sword(w);
          break;
        case frame::kGlobalControl:
          hls::write_control(m.globals, w & frame::kControlFloor, w & frame::kControlPlate,
                             w & frame::kControlPlateHold);
          break;
        case frame::kGlobalSweepPeriod:
          m.period = w & frame::kCountMask;
          break;
        default:
          m.status |= hls::kStatusBadCommand;
      }
      return;
    case frame::kRegionParticleState:
    case frame::kRegionSweepParticle: {
      std::uint32_t lane = 0, local = 0;
      if (!locate(index, lane, local)) {
        if (field == wpe - 1) m.status |= hls::kStatusBadCommand;
        return;
      }
      if (region == frame::kRegionSweepParticle) {
        m.stat[index] = w & ((1u << hls::kSweepStaticBits) - 1);
        return;
      }
      (field < 3 ? m.x[index][field] : m.p[index][field - 3]) = sword(w);
      // The lane above keeps a ghost copy of this slab's last particles.
      if (int(lane) + 1 < lanes_) {
        const hls::SweepLaneRegs& l = m.lane[lane];
        const std::uint32_t ghost = m.lane[lane + 1].ghost;
        if (ghost != 0 && local + ghost >= l.count) {
          const std::uint32_t a = local - (l.count - ghost);
          (field < 3 ? m.ghost_x[lane + 1][a][field] : m.ghost_p[lane + 1][a][field - 3]) = sword(w);
        }
      }
      return;
    }
    case frame::kRegionSweepEdge: {
      const std::uint32_t lane = index >> hls::kSweepSlotLaneShift;
      const std::uint32_t n = index & (hls::kSweepSramWords - 1);
      if (field == 0) {
        d_word_ = w;
        return;
      }
      if (lane >= std::uint32_t(lanes_)) {
        m.status |= hls::kStatusBadCommand;
        return;
      }
      hls::SweepEdgeWord e;
      e.d = sword(d_word_);
      e.set_tag(w);
      m.sram[lane][n] = e.pack();
      return;
    }
    case frame::kRegionSweepLane: {
      // Gathered and committed with the last word, all or nothing (rtl/rheo_sweep_ctrl.sv).
      const std::uint32_t v = w & frame::kCountMask;
      if (field < frame::kSweepLaneDelay) {
        lane_words_[field] = v;
        return;
      }
      if (index >= std::uint32_t(lanes_) || lane_words_[frame::kSweepLaneCount] > std::uint32_t(slab_depth_) ||
          lane_words_[frame::kSweepLaneGhost] > std::uint32_t(ghost_depth_) ||
          (index == 0 && lane_words_[frame::kSweepLaneGhost] != 0)) {
        m.status |= hls::kStatusBadCommand;
        return;
      }
      m.lane[index] = {lane_words_[frame::kSweepLaneFirst], lane_words_[frame::kSweepLaneCount],
                       lane_words_[frame::kSweepLaneGhost], v};
      return;
    }
    case frame::kRegionSweepOffset:
      if (index < std::uint32_t(hls::kSweepOffsets)) m.offset[index] = w & hls::kSweepMaxOffset;
      return;
    case frame::kRegionSweepClass:
      if (index >= std::uint32_t(hls::kSweepEdgeClasses)) return;
      if (field == 0)
        m.class_len[index] = sword(w);
      else
        m.class_material[index] = w & (hls::kMaxMaterials - 1);
      return;
    case frame::kRegionSweepMass:
      if (index < std::uint32_t(hls::kSweepMassClasses)) m.mass_minv[index] = hls::unpack_coef(w);
      return;
    case frame::kRegionMaterial: {
      if (index >= std::uint32_t(hls::kMaxMaterials)) return;
      hls::MaterialCoefs& mc = m.materials[index];
      hls::Coef* coefs[6] = {&mc.alpha, &mc.beta, &mc.kt, &mc.ct, &mc.a_min, &mc.a_max};
      if (field < 6)
        *coefs[field] = hls::unpack_coef(w);
      else
        mc.flags = w & 3u;
      return;
    }
    default:
      return;
  }
}

std::uint32_t SweepBitTrueTransport::read_word(std::uint32_t region, std::uint32_t index,
                                               std::uint32_t field) {
  hls::SweepMemory& m = *mem_;
  if (particle_region(region)) {
    std::uint32_t lane = 0, local = 0;
    if (!locate(index, lane, local)) {
      m.status |= hls::kStatusBadCommand;
      return 0;
    }
    if (region == frame::kRegionSweepParticle) return m.stat[index];
    return static_cast<std::uint32_t>(field < 3 ? m.x[index][field] : m.p[index][field - 3]);
  }
  if (slot_region(region)) {
    const std::uint32_t lane = index >> hls::kSweepSlotLaneShift;
    if (lane >= std::uint32_t(lanes_)) {
      m.status |= hls::kStatusBadCommand;
      return 0;
    }
    const hls::SweepEdgeWord e =
        hls::SweepEdgeWord::unpack(m.sram[lane][index & (hls::kSweepSramWords - 1)]);
    return field == 0 ? static_cast<std::uint32_t>(e.d) : e.tag();
  }
  if (region == frame::kRegionSweepLane) {
    if (index >= std::uint32_t(lanes_)) {
      m.status |= hls::kStatusBadCommand;
      return 0;
    }
    const hls::SweepLaneRegs& l = m.lane[index];
    const std::uint32_t words[4] = {l.first, l.count, l.ghost, l.delay};
    return words[field & 3u];
  }
  return 0;
}

void SweepBitTrueTransport::process() {
  hls::SweepMemory& m = *mem_;
  while (!in_.empty()) {
    const std::uint32_t h = in_.front();
    const std::uint32_t op = frame::header_opcode(h);
    const std::uint32_t region = frame::header_region(h);
    const std::uint32_t count = frame::header_count(h);
    if (op == frame::kOpWrite || op == frame::kOpRead) {
      if (region >= frame::kNumRegions || !region_ok(region, op == frame::kOpWrite)) {
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
      in_.pop_front();
      hls::start_step(m.globals, sword(in_.front()));
      in_.pop_front();
      const std::int64_t plate_force = hls::sweep_step<Fmt>(m);
      out_.push_back(static_cast<std::uint32_t>(plate_force));
      // A step that follows another of its command starts the period after it.
      cycles_ += static_cast<std::uint32_t>(continued_ ? hls::sweep_period(m) : hls::sweep_cycles(m));
      continued_ = count > 1;
      if (continued_) in_.push_front(frame::header(frame::kOpRun, frame::kRegionGlobals, count - 1));
    } else if (op == frame::kOpStatus) {
      in_.pop_front();
      out_.push_back(m.status);
      out_.push_back(m.step_count);
      out_.push_back(cycles_);
      out_.push_back(std::uint32_t(lanes_) | frame::kStatusLanesSweep);
      if (count & frame::kStatusClear) m.status = 0;
    } else {
      m.status |= hls::kStatusBadCommand;
      in_.pop_front();
    }
  }
}

}  // namespace rheo::driver
