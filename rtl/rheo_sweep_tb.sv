// The sweep core as Verilator runs it: rheo_sweep_core with its board SRAM, two IDT71V3556
// models per lane (rheo_zbt_sram) on the core's pins. Its ports are the core's stream
// ports, so the host's Verilator transport drives it as it drives rheo_core. Simulation
// only: the SRAM models are a testbench's, not the design's.
module rheo_sweep_tb #(
  parameter int Lanes = 5,
  parameter int SlabDepth = 1024,
  parameter int GhostDepth = 256,
  parameter int W = 32
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  input  logic [W-1:0] s_axis_tdata,
  input  logic         s_axis_tvalid,
  output logic         s_axis_tready,
  input  logic         s_axis_tlast,
  output logic [W-1:0] m_axis_tdata,
  output logic         m_axis_tvalid,
  input  logic         m_axis_tready,
  output logic         m_axis_tlast,
  output logic         busy_o
);
  localparam int NW = rheo_consts_pkg::ZbtAddrBits;
  localparam int DW = rheo_consts_pkg::ZbtWordBits;
  localparam int Devs = 2 * Lanes;
  logic [Devs*NW-1:0] a;
  logic [Devs-1:0] ce_n, we_n, d_oe, q_oe;
  logic [Devs*DW-1:0] d, q;
  rheo_sweep_core #(.Lanes(Lanes), .SlabDepth(SlabDepth), .GhostDepth(GhostDepth), .W(W)) rheo_core (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast), .busy_o(busy_o),
    .zbt_a_o(a), .zbt_ce_n_o(ce_n), .zbt_we_n_o(we_n), .zbt_d_o(d), .zbt_d_oe_o(d_oe),
    .zbt_q_i(q));
  for (genvar b = 0; b < Devs; b++) begin : g_sram
    rheo_zbt_sram u_sram (
      .clk_i(clk_i), .a_i(a[b*NW +: NW]), .cen_n_i(1'b0), .ce_n_i(ce_n[b]), .we_n_i(we_n[b]),
      .adv_i(1'b0), .d_i(d[b*DW +: DW]), .d_oe_i(d_oe[b]), .q_o(q[b*DW +: DW]),
      .q_oe_o(q_oe[b]));
  end
  logic unused;
  assign unused = ^q_oe;
endmodule
