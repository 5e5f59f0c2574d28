// Simulation model of one IDT71V3556 (128K x 36 ZBT SRAM with pipelined outputs; IDT
// data sheet DSC-5281: "Address and control signals are applied to the SRAM during one
// clock cycle, and two cycles later the associated data cycle occurs, be it read or
// write"; 166 MHz for the x36 part). Testbench only (rtl/rheo_sweep_tb.sv), never
// synthesised. Clock by clock:
//   edge n    the device samples CE1#, R/W# and the address (with CEN# low)
//   edge n+1  a read's word leaves the output register: on the bus during clock n+1
//   edge n+2  the controller samples the read word; a write's word is sampled from the bus
// CEN# high suspends the device for the clock (every synchronous input ignored, the
// pipeline holds). ADV/LD high (burst advance) is not modelled: the core never uses it,
// and the model stops the simulation if it sees it, as it does for two drivers on the
// data bus and for a read of a word whose write is still in the pipeline (the device's
// internal forwarding is not modelled either).
module rheo_zbt_sram #(
  localparam int AW = rheo_consts_pkg::ZbtAddrBits,
  localparam int DW = rheo_consts_pkg::ZbtWordBits
) (
  input  logic          clk_i,
  input  logic [AW-1:0] a_i,
  input  logic          cen_n_i,
  input  logic          ce_n_i,
  input  logic          we_n_i,
  input  logic          adv_i,
  input  logic [DW-1:0] d_i,      // the bus as the controller drives it
  input  logic          d_oe_i,   // the controller drives the bus
  output logic [DW-1:0] q_o,      // the bus as the device drives it
  output logic          q_oe_o    // the device drives the bus
);
  logic [DW-1:0] mem [2**AW];
  logic v1_q = 1'b0, w1_q = 1'b0, v2_q = 1'b0, w2_q = 1'b0;
  logic [AW-1:0] a1_q, a2_q;
  always_ff @(posedge clk_i) begin
    if (!cen_n_i) begin
      if (v2_q && w2_q) mem[a2_q] <= d_i;
      q_oe_o <= v1_q && !w1_q;
      if (v1_q && !w1_q) q_o <= mem[a1_q];
      v2_q <= v1_q;
      w2_q <= w1_q;
      a2_q <= a1_q;
      v1_q <= !ce_n_i;
      w1_q <= !we_n_i;
      a1_q <= a_i;
    end
  end
  // The controller's side of the data cycle: a write's data is on the bus in the clock
  // before the device samples it, a read's word is on the bus while the device drives it.
  always_ff @(posedge clk_i) begin
    if (!cen_n_i) begin
      assert (!(v2_q && w2_q) || d_oe_i)
        else $error("rheo_zbt_sram: write data cycle without the controller driving the bus");
      assert (!(q_oe_o && d_oe_i)) else $error("rheo_zbt_sram: two drivers on the data bus");
      assert (!(!ce_n_i && adv_i)) else $error("rheo_zbt_sram: burst advance is not modelled");
      assert (!(v1_q && !w1_q && v2_q && w2_q && a1_q == a2_q))
        else $error("rheo_zbt_sram: read of a word whose write is still in the pipeline");
    end
  end
endmodule
