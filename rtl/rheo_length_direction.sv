// A vector's length and direction, as the TEM computes them for an edge's r and the tool unit
// for the particle's offset r' and its slide dp_t (rheo::hls::length_direction):
//   r block-normalised (r^, shift), l2n = r^.r^ exact, y = rsqrt(l2n) = 2^-k / sqrt(m 2^parity),
//   l = |r| = m y 2^(shift + parity + k - (2B-3))     (the format of r)
//   u = r / |r| = r^ y 2^-(k+1)                       (Q1.(B-2) operands)
// Stages (latency 20): 1-3 normalisation, 4 squares, 5-6 their exact sum, 7-17 rsqrt,
// 18 m y and r^ y, 19-20 rounded shifts. Multipliers: 3 squares, 3 in the rsqrt, 4 products:
// 10 MULT18X18 for B = 18. One vector per clock.
module rheo_length_direction #(
  parameter int W = 32,   // word width of r and l
  parameter int B = 18,   // operand width (rheo_consts_pkg::OperandBits)
  parameter int EW = 6    // normalisation exponent width (< W - B + 2)
) (
  input  logic               clk_i,
  input  logic               rst_ni,      // delay-line pointers only
  input  logic [3*W-1:0]     v_i,         // r, word i at [i*W +: W]
  output logic signed [W-1:0] l_o,
  output logic [3*B-1:0]     u_o,         // u, operand i at [i*B +: B]
  output logic               clip_o,      // l or a component of u saturated
  output logic               degenerate_o // r = 0 (u = 0, l = 0)
);
  localparam int PW = 2 * B;  // product width

  // ---- stages 1-3: r^ and its shift ----
  logic [3*B-1:0] vn3_flat;
  logic signed [B-1:0] vn3 [3];
  logic [EW-1:0] e3;
  rheo_normalize #(.N(3), .InW(W), .B(B), .ShiftW(EW)) u_norm (
    .clk_i(clk_i), .v_i(v_i), .mant_o(vn3_flat), .shift_o(e3));
  always_comb for (int i = 0; i < 3; i++) vn3[i] = vn3_flat[i*B +: B];

  // ---- stages 4-6: l2n = r^.r^ (exact) ----
  logic signed [PW-1:0] sq4_q [3];
  logic [PW-1:0] s01_5_q, sq2_5_q, l2n6_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) sq4_q[i] <= vn3[i] * vn3[i];
    s01_5_q <= sq4_q[0] + sq4_q[1];
    sq2_5_q <= sq4_q[2];
    l2n6_q <= s01_5_q + sq2_5_q;
  end

  // ---- stages 7-17: y = 1/sqrt(l2n); r^ and its shift wait for it ----
  logic signed [B-1:0] rs_mant17, rs_y17;
  logic rs_parity17, rs_deg17;
  logic [5:0] rs_k17;
  rheo_rsqrt #(.B(B)) u_rsqrt (
    .clk_i(clk_i), .rst_ni(rst_ni), .l2_i(l2n6_q), .mant_o(rs_mant17), .y_o(rs_y17),
    .parity_o(rs_parity17), .k_o(rs_k17), .degenerate_o(rs_deg17));
  logic [3*B-1:0] vn17_flat;
  logic [EW-1:0] e17;
  rheo_delay #(.W(3*B), .N(14)) u_vn_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(vn3_flat), .q_o(vn17_flat));
  rheo_delay #(.W(EW), .N(14)) u_e_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(e3), .q_o(e17));

  // ---- stage 18: m y, r^ y; stages 19-20: l, u ----
  logic signed [PW-1:0] lprod18_q, uprod18_q [3];
  logic [6:0] ls18_q, us18_q;
  logic deg18_q, deg19_q;
  always_ff @(posedge clk_i) begin
    lprod18_q <= rs_mant17 * rs_y17;
    for (int i = 0; i < 3; i++) uprod18_q[i] <= $signed(vn17_flat[i*B +: B]) * rs_y17;
    // both >= 0: shift + parity + k <= 15 + 18 = 2B - 3 (l2n < 2^36 gives k <= 17)
    ls18_q <= 7'(2 * B - 3) - 7'(e17) - 7'(rs_parity17) - 7'(rs_k17);
    us18_q <= 7'(rs_k17) + 7'd1;
    deg18_q <= rs_deg17;
    deg19_q <= deg18_q;
    degenerate_o <= deg19_q;
  end
  logic clip_l20;
  logic [2:0] clip_u20;
  rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_l (
    .clk_i(clk_i), .v_i(lprod18_q), .sb_i(ls18_q), .out_o(l_o), .clip_o(clip_l20));
  for (genvar i = 0; i < 3; i++) begin : g_u
    logic signed [B-1:0] u20;
    rheo_round_shift #(.InW(PW), .OutW(B), .ShiftW(7), .MaxLeft(0)) u_u (
      .clk_i(clk_i), .v_i(uprod18_q[i]), .sb_i(us18_q), .out_o(u20), .clip_o(clip_u20[i]));
    assign u_o[i*B +: B] = u20;
  end
  assign clip_o = clip_l20 | (|clip_u20);
endmodule
