// The harness of one verilated core class M (included by the core plug-ins only,
// host/driver/core_plugin.cpp.in): words pushed into s_axis and pulled from m_axis clock by
// clock, with optional random idle cycles on the input side and random back-pressure on the
// output side (seeded), an optional FST waveform, and a failed RTL assertion turned into
// rheo::Error.
#pragma once

// Verilator's runtime headers are not written for -Wextra -Werror.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>
#include <verilated_fst_c.h>
#pragma GCC diagnostic pop

#include <chrono>
#include <deque>
#include <memory>
#include <random>
#include <string>

#include "host/driver/core_harness.hpp"
#include "sim/error.hpp"

namespace rheo::driver {

template <class M>
class Harness : public CoreHarness {
 public:
  explicit Harness(const VerilatorOptions& o) : opt_(o), rng_(o.seed) {
    ctx_ = std::make_unique<VerilatedContext>();
    ctx_->traceEverOn(!o.trace_fst.empty());
    // A failed assertion sets the context's error flag instead of aborting the process,
    // so that eval() can turn it into rheo::Error.
    ctx_->fatalOnError(false);
    if (o.power_up_seed != 0) {
      // Random power-up state, drawn in the model's constructor (--x-initial unique).
      ctx_->randReset(2);
      ctx_->randSeed(int(o.power_up_seed));
    }
    model_ = std::make_unique<M>(ctx_.get(), "rheo_core");
    if (!o.trace_fst.empty()) {
      // The power-up variant is built without tracing (rtl/CMakeLists.txt).
      if constexpr (requires(M& m, VerilatedFstC* f) { m.trace(f, 99); }) {
        fst_ = std::make_unique<VerilatedFstC>();
        model_->trace(fst_.get(), 99);
        fst_->open(o.trace_fst.c_str());
        if (!fst_->isOpen()) throw Error("cannot open trace file " + o.trace_fst);
      } else {
        throw Error("RTL core: this variant is built without waveform tracing");
      }
    }
    // Reset. The core's registers have asynchronous resets, which in the hardware act for
    // as long as rst_ni is low, but a simulator only runs them on rst_ni's falling edge
    // (or on a clock edge while it is low). A reset held low from time 0 has no falling
    // edge, so until the first clock the registers keep their power-up values, and a
    // random power-up state can show a word on m_axis. So rst_ni first goes high and
    // then falls, and no handshake is driven or taken until it is released.
    model_->clk_i = 0;
    model_->rst_ni = 1;
    model_->s_axis_tvalid = 0;
    model_->s_axis_tlast = 0;
    model_->m_axis_tready = 0;
    eval();
    model_->rst_ni = 0;
    eval();
    in_reset_ = true;
    for (int i = 0; i < kResetClocks; ++i) tick();
    model_->rst_ni = 1;
    in_reset_ = false;
    tick();
  }
  ~Harness() override {
    model_->final();
    if (fst_) fst_->close();
  }

  void send(const std::vector<std::uint32_t>& words) override {
    in_.insert(in_.end(), words.begin(), words.end());
    std::uint64_t idle = 0;
    while (!in_.empty()) {
      const std::size_t before = in_.size() + out_.size();
      tick();
      idle = (in_.size() + out_.size() == before) ? idle + 1 : 0;
      if (idle > opt_.timeout_cycles) throw Error("RTL core: input not accepted (timeout)");
    }
  }

  std::vector<std::uint32_t> receive(std::size_t n) override {
    std::uint64_t idle = 0;
    while (out_.size() < n) {
      const std::size_t before = out_.size();
      tick();
      idle = (out_.size() == before) ? idle + 1 : 0;
      if (idle > opt_.timeout_cycles) {
        throw Error("RTL core: expected " + std::to_string(n) + " response words, got " +
                    std::to_string(out_.size()) + " (timeout)");
      }
    }
    std::vector<std::uint32_t> got(out_.begin(), out_.begin() + n);
    out_.erase(out_.begin(), out_.begin() + n);
    return got;
  }

  std::uint64_t time() const override { return ctx_->time(); }

 private:
  // Evaluates the model; a failed RTL assertion ($error under --assert) ends the run.
  void eval() {
    model_->eval();
    if (ctx_->gotError()) {
      throw Error("RTL core: an assertion failed at clock " + std::to_string(cycles) +
                  " (message above)");
    }
  }

  // One clock: drive inputs for this cycle, sample handshakes at the rising edge.
  void tick() {
    const auto t0 = std::chrono::steady_clock::now();
    // The model's runtime (assertion reports, random state) goes through the thread's
    // context; another transport in this thread may have made its own the current one.
    Verilated::threadContextp(ctx_.get());
    // Idle cycles only between words: a word once offered stays offered until the core
    // takes it (AXI4-Stream; rheo_stream_checker asserts it).
    const bool offer = !in_reset_ && !in_.empty() &&
                       (offered_ || !(opt_.input_idle_prob > 0 && coin(opt_.input_idle_prob)));
    model_->s_axis_tvalid = offer;
    model_->s_axis_tdata = offer ? in_.front() : 0;
    model_->s_axis_tlast = offer && in_.size() == 1;
    model_->m_axis_tready =
        !in_reset_ && !(opt_.output_stall_prob > 0 && coin(opt_.output_stall_prob));
    model_->clk_i = 0;
    eval();
    const bool in_fire = model_->s_axis_tvalid && model_->s_axis_tready;
    const bool out_fire = model_->m_axis_tvalid && model_->m_axis_tready;
    const std::uint32_t out_word = model_->m_axis_tdata;
    const bool out_last = model_->m_axis_tlast;
    if (fst_ && tracing) fst_->dump(ctx_->time());
    ctx_->timeInc(1);
    model_->clk_i = 1;
    eval();
    if (fst_ && tracing) fst_->dump(ctx_->time());
    ctx_->timeInc(1);
    offered_ = offer && !in_fire;
    if (in_fire) in_.pop_front();
    if (out_fire) {
      out_.push_back(out_word);
      ++open_frame;
      if (out_last) {
        frame_lengths.push_back(open_frame);
        open_frame = 0;
      }
    }
    ++cycles;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  bool coin(double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < p; }

  static constexpr int kResetClocks = 4;
  VerilatorOptions opt_;
  bool in_reset_ = false;
  bool offered_ = false;  // the word at in_.front() was offered and not yet taken
  std::mt19937_64 rng_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> model_;
  std::unique_ptr<VerilatedFstC> fst_;
  std::deque<std::uint32_t> in_, out_;
};

}  // namespace rheo::driver
