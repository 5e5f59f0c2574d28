// Protocol and state checker for rheo_core: instantiated by the core outside synthesis
// (`ifndef SYNTHESIS), so every verilated core built with --assert checks it on every clock,
// and the formal flow (tests/formal) proves the core's side of it with Yosys.
//
// The properties are written with registered copies of the previous clock's handshake and
// immediate assertions, which Verilator and Yosys' read_verilog -formal read alike.
//
// Stream rules (AXI4-Stream): once valid is high it stays high, with the same data and
// last, until the clock where ready is high.
//   s_axis: a property of whatever drives the core. It is assumed in the formal proof and
//           asserted in simulation, where a failure names the testbench.
//   m_axis: a property of the core.
// Core invariants: the FSM state is one of the enum's values; the core offers an output
// word exactly in the states that hold one, and never takes an input word while it offers
// one; it does not take input while busy; the bank, drain and division counters and the
// division's remainder (which becomes the bank) stay in their ranges.
// Yosys 0.23 takes no action block after an immediate assertion: the message is for
// simulation only.
// Synthesis reads this file too (it is in the core's one source list, rtl/sources.cmake)
// but never elaborates the module (`ifndef SYNTHESIS at its instance); the action block
// still has to parse.
`ifdef SYNTHESIS
`define RHEO_CHECK(cond, msg) assert (cond);
`elsif FORMAL
`define RHEO_CHECK(cond, msg) assert (cond);
`else
`define RHEO_CHECK(cond, msg) assert (cond) else $error(msg);
`endif

module rheo_stream_checker #(
  parameter int W = 32,
  parameter int StateW = 5,
  parameter int NumStates = 17,   // legal states are 0 .. NumStates - 1
  parameter int Lanes = 1,
  parameter int BW = 1,
  parameter int DrainW = 6,
  parameter int MaxDrain = 43,    // largest value the drain counter is loaded with
  parameter int DivStepW = 5,
  parameter int DivSteps = 24     // the division's clocks; its counter ends one past
) (
  input logic              clk_i,
  input logic              rst_ni,
  input logic [W-1:0]      s_axis_tdata,
  input logic              s_axis_tvalid,
  input logic              s_axis_tready,
  input logic              s_axis_tlast,
  input logic [W-1:0]      m_axis_tdata,
  input logic              m_axis_tvalid,
  input logic              m_axis_tready,
  input logic              m_axis_tlast,
  input logic              busy_i,
  input logic [StateW-1:0] state_i,
  input logic              holds_word_i,   // the state is one that sends a word
  input logic [BW-1:0]     bank_i,
  input logic [BW-1:0]     div_rem_i,      // remainder of the start-index division
  input logic [DrainW-1:0] drain_i,
  input logic [DivStepW-1:0] div_step_i
);
  // The previous clock, taken only out of reset: past_ok_q is cleared at once by a reset
  // (asynchronous) and set by the first clock after it, so no check looks across a reset.
  logic past_ok_q;
  logic in_stall_q, out_stall_q;
  logic [W-1:0] in_data_q, out_data_q;
  logic in_last_q, out_last_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      past_ok_q <= 1'b0;
      in_stall_q <= 1'b0;
      out_stall_q <= 1'b0;
    end else begin
      past_ok_q <= 1'b1;
      in_stall_q <= s_axis_tvalid && !s_axis_tready;
      out_stall_q <= m_axis_tvalid && !m_axis_tready;
    end
  end
  always_ff @(posedge clk_i) begin
    in_data_q <= s_axis_tdata;
    in_last_q <= s_axis_tlast;
    out_data_q <= m_axis_tdata;
    out_last_q <= m_axis_tlast;
  end

`ifdef FORMAL
  // The proof starts in reset: the first clock of every trace has rst_ni low.
  logic first_q = 1'b1;
  always_ff @(posedge clk_i) first_q <= 1'b0;
  always_comb if (first_q) assume (!rst_ni);
`endif

  logic in_held, out_held;
  assign in_held = s_axis_tvalid && s_axis_tdata == in_data_q && s_axis_tlast == in_last_q;
  assign out_held = m_axis_tvalid && m_axis_tdata == out_data_q && m_axis_tlast == out_last_q;

  // Checked at the clock edge on the values of the clock that ends (sampled as a concurrent
  // assertion would be), against the registered copies of the clock before.
  always_ff @(posedge clk_i) begin
    if (past_ok_q && in_stall_q) begin
`ifdef FORMAL
      assume (in_held);
`else
      `RHEO_CHECK(in_held, "s_axis: testbench withdrew or changed a word before s_axis_tready")
`endif
    end
  end

  always_ff @(posedge clk_i) begin
    if (past_ok_q) begin
      `RHEO_CHECK(!out_stall_q || out_held,
                  "m_axis: core withdrew or changed a word before m_axis_tready")
      `RHEO_CHECK(state_i < StateW'(NumStates), "rheo_core: FSM state out of its enum")
      `RHEO_CHECK(m_axis_tvalid == holds_word_i,
                  "rheo_core: m_axis_tvalid outside the sending states")
      `RHEO_CHECK(!(s_axis_tready && m_axis_tvalid),
                  "rheo_core: ready for input while it offers an output word")
      `RHEO_CHECK(!(s_axis_tready && busy_i), "rheo_core: ready for input while busy")
      `RHEO_CHECK({1'b0, bank_i} < (BW+1)'(Lanes), "rheo_core: bank counter beyond the lanes")
      `RHEO_CHECK({1'b0, div_rem_i} < (BW+1)'(Lanes),
                  "rheo_core: division remainder beyond the lanes")
      `RHEO_CHECK(drain_i <= DrainW'(MaxDrain), "rheo_core: drain counter out of range")
      `RHEO_CHECK(div_step_i <= DivStepW'(DivSteps), "rheo_core: division counter out of range")
    end
  end
endmodule

`undef RHEO_CHECK
