// Reciprocal of a positive word v (rheo::hls::recip_s, and 1/L in rheo::hls::hardening_h):
// v = m 2^(nb - 1) with m in [1, 2) rounded to a Q1.(B-2) operand, y ~ 1/m in Q1.(B-2) (at
// most 1) from the seed table over m's top RecipIndexBits fraction bits and one
// Newton-Raphson step y0 (2 - m y0) (rheo::hls::recip_mantissa). 1/v = y 2^-(B-2) 2^(1-nb).
// v <= 0 raises nonpos_o and gives y = 1 and nb = NonPosNb.
// Register index t of each value (v_i is stage 0): 1 nb, 3 m, 4 seed y0, 5 m y0,
// 6 2 - m y0, 7 y0 (2 - m y0), 8 y (outputs). Multipliers: 2. With LenStages = 2 the bit
// length takes two stages (rheo_bitlen, for wide words) and every later index is one more.
module rheo_recip #(
  parameter int InW = 48,
  parameter int NonPosNb = 0,
  parameter int LenStages = 1,  // 1 or 2
  localparam int B = rheo_consts_pkg::OperandBits
) (
  input  logic                  clk_i,
  input  logic signed [InW-1:0] v_i,       // stage 0
  output logic signed [B-1:0]   y_o,       // stage 8
  output logic [5:0]            nb_o,      // bit length of v (NonPosNb when v <= 0)
  output logic                  nonpos_o   // v <= 0
);
  localparam int PW = 2 * B;
  localparam int RIdxB = rheo_consts_pkg::RecipIndexBits;

  if (InW - 1 > 63) begin : g_width_check
    $error("rheo_recip: nb must fit six bits");
  end

  // ---- stage 1 (or 1-2): bit length ----
  logic [5:0] nb1_q;
  logic signed [InW-1:0] v1_q;
  logic nonpos1_q;
  if (LenStages == 1) begin : g_len1
    // found in parallel (bit b leads iff no higher bit is set)
    logic [5:0] nb_w;
    logic [InW-2:0] higher;
    always_comb begin
      higher[InW-2] = 1'b0;
      for (int b = InW - 3; b >= 0; b--) higher[b] = higher[b+1] | v_i[b+1];
      nb_w = '0;
      for (int b = 0; b < InW - 1; b++) nb_w = nb_w | ((v_i[b] & ~higher[b]) ? 6'(b + 1) : 6'd0);
    end
    always_ff @(posedge clk_i) begin
      nb1_q <= nb_w;
      v1_q <= v_i;
      nonpos1_q <= v_i[InW-1] || v_i == '0;
    end
  end else begin : g_len2
    // two stages; v and its sign wait one clock (a negative v's bit length is not used)
    logic signed [InW-1:0] v_q;
    logic nonpos_q;
    rheo_bitlen #(.InW(InW - 1), .NW(6)) u_len (.clk_i(clk_i), .v_i(v_i[InW-2:0]), .n_o(nb1_q));
    always_ff @(posedge clk_i) begin
      v_q <= v_i;
      nonpos_q <= v_i[InW-1] || v_i == '0;
      v1_q <= v_q;
      nonpos1_q <= nonpos_q;
    end
  end
  if (LenStages != 1 && LenStages != 2) begin : g_len_check
    $error("rheo_recip: LenStages must be 1 or 2");
  end

  // ---- stages 2-3: m = v 2^-(nb - (B-1)) (rounding up to 2 is held at the largest operand) ----
  logic signed [B-1:0] mr3;
  logic unused_clip_mr;
  rheo_round_shift #(.InW(InW), .OutW(B), .ShiftW(7), .MaxLeft(B - 2)) u_m (
    .clk_i(clk_i), .v_i(v1_q), .sb_i(7'(nb1_q) - 7'd1), .out_o(mr3), .clip_o(unused_clip_mr));

  // ---- stages 4-8: seed, then y0 (2 - m y0) ----
  logic signed [B-1:0] mr4_q, y0_4_q, y0_5_q, y0_6_q, e6_q, y8_q;
  logic signed [PW-1:0] my5_q, yp7_q;
  always_ff @(posedge clk_i) begin
    mr4_q <= mr3;
    y0_4_q <= B'(rheo_consts_pkg::recip_seed(mr3[B-3 -: RIdxB]));
    my5_q <= mr4_q * y0_4_q;
    y0_5_q <= y0_4_q;
    e6_q <= B'(1 << (B - 1)) - B'((my5_q + PW'(1 << (B - 3))) >>> (B - 2));
    y0_6_q <= y0_5_q;
    yp7_q <= y0_6_q * e6_q;
  end
  logic nonpos7;
  logic [5:0] nb7;
  rheo_delay #(.W(1), .N(6)) u_np_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(nonpos1_q), .q_o(nonpos7));
  rheo_delay #(.W(6), .N(6)) u_nb_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(nb1_q), .q_o(nb7));
  logic signed [PW-1:0] yr_w;
  always_comb yr_w = (yp7_q + PW'(1 << (B - 3))) >>> (B - 2);
  always_ff @(posedge clk_i) begin
    if (nonpos7 || yr_w > PW'(1 << (B - 2))) y8_q <= B'(1 << (B - 2));
    else y8_q <= B'(yr_w);
    nb_o <= nonpos7 ? 6'(NonPosNb) : nb7;
    nonpos_o <= nonpos7;
  end
  assign y_o = y8_q;

  logic unused;
  assign unused = unused_clip_mr;
endmodule
