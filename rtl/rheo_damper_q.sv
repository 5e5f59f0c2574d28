// The force-dependent series damper's state for a spring extension a >= 0 (seed 000 §3.3;
// rheo::hls::damper_q and damper_s):
//   z = zk * clamp(a - d_lo, 0, d_span)   (log2 of c2_max / c2, DamperFracZ fraction bits)
//   q = 2^-z = qm 2^-(B-2) 2^-n           (2^-f table over the top Exp2IndexBits fraction
//                                          bits, linear interpolation; n = floor(z))
//   s = s_base + s_c2 q                   (c / c_ref, DamperFracS fraction bits, SW wide)
// Shared by rheo_damper (a = |d - L|) and rheo_harden with the damper (a = g |d - L|, the
// hardened spring's extension), so both follow one bit-true definition.
// Register index t of each value (coef_i is stage 0, a_i stage 2):
//    2 d_lo and d_span as words, s_base as a word
//    3 a - d_lo           4 clamped (W + 4 bits)        7 normalised
//    8 zk product         10 z                          11 z >= 0, table entries
//   12 entry difference   13 times the fraction         14 qm = 2^-frac(z), n
//   15 s_c2 qm            17 as a word                  18 s
// Multipliers: 1 (zk) + 1 (interpolation) + 1 (s_c2 q) = 3.
module rheo_damper_q #(
  parameter int W = 32,
  parameter int CoefW = 24,
  parameter int AW = 33,   // width of a (signed, a >= 0), at most W + 3
  parameter int SW = 40    // width of s (rheo_consts_pkg::DamperSBits or HardSBits)
) (
  input  logic                  clk_i,
  input  logic [5*CoefW-1:0]    coef_i,  // {s_c2, s_base, zk, d_span, d_lo} (stage 0)
  input  logic signed [AW-1:0]  a_i,     // the spring's extension, >= 0 (stage 2)
  output logic signed [rheo_consts_pkg::OperandBits-1:0] qm_o,    // Q1.16 in [1/2, 1] (stage 14)
  output logic [5:0]            n_o,     // (stage 14)
  output logic signed [SW-1:0]  s_o,     // (stage 18)
  output logic                  clip_o   // z or s saturated (stage 18)
);
  localparam int B = rheo_consts_pkg::OperandBits;
  localparam int PW = 2 * B;
  localparam int FracX = rheo_consts_pkg::FracX;
  localparam int MantW = rheo_consts_pkg::CoefMantBits;
  localparam int Bias = rheo_consts_pkg::CoefShiftBias;
  localparam int FracZ = rheo_consts_pkg::DamperFracZ;
  localparam int ZW = rheo_consts_pkg::DamperZBits;
  localparam int IdxB = rheo_consts_pkg::Exp2IndexBits;
  localparam int InterpB = FracZ - IdxB;
  localparam int TabB = rheo_consts_pkg::Exp2TableBits;
  localparam int FracS = rheo_consts_pkg::DamperFracS;
  localparam int EW = 6;
  localparam int CDlo = 0, CDspan = 1, CZk = 2, CSbase = 3, CSc2 = 4;
  localparam int Last = 18;

  if (B != 18 || TabB != B - 2) begin : g_width_check
    $error("rheo_damper_q: the table is Q1.16 operands of 18-bit products");
  end
  if (AW > W + 3) begin : g_a_check
    $error("rheo_damper_q: a - d_lo must fit W + 4 bits");
  end

  logic [CoefW-1:0] c0 [5];
  always_comb for (int c = 0; c < 5; c++) c0[c] = coef_i[c*CoefW +: CoefW];

  // ---- flags: each clip joins in the stage where it is seen ----
  logic flag_at [Last+1];
  logic fl_q [Last+1];
  always_ff @(posedge clk_i) begin
    fl_q[0] <= 1'b0;
    for (int s = 1; s <= Last; s++) fl_q[s] <= fl_q[s-1] | flag_at[s-1];
  end
  assign clip_o = fl_q[Last] | flag_at[Last];

  // ---- stages 1-2: d_lo, d_span, s_base as words (coefficient mant 2^-(shift - frac)) ----
  // d_lo and d_span saturate quietly at W + 2 bits: beyond it the clamp below gives the
  // same result as the exact value would (hls::damper_q holds them the same way).
  logic signed [W+1:0] dlo2, dspan2;
  logic signed [SW-1:0] sbase2;
  logic unused_clip_dlo, unused_clip_dspan, clip_sbase2;
  rheo_round_shift #(.InW(MantW), .OutW(W+2), .ShiftW(7), .MaxLeft(Bias + FracX)) u_dlo (
    .clk_i(clk_i), .v_i($signed(c0[CDlo][MantW-1:0])), .sb_i(7'(c0[CDlo][CoefW-1:MantW])), .out_o(dlo2),
    .clip_o(unused_clip_dlo));
  rheo_round_shift #(.InW(MantW), .OutW(W+2), .ShiftW(7), .MaxLeft(Bias + FracX)) u_dspan (
    .clk_i(clk_i), .v_i($signed(c0[CDspan][MantW-1:0])), .sb_i(7'(c0[CDspan][CoefW-1:MantW])), .out_o(dspan2),
    .clip_o(unused_clip_dspan));
  rheo_round_shift #(.InW(MantW), .OutW(SW), .ShiftW(7), .MaxLeft(Bias + FracS)) u_sbase (
    .clk_i(clk_i), .v_i($signed(c0[CSbase][MantW-1:0])), .sb_i(7'(c0[CSbase][CoefW-1:MantW])), .out_o(sbase2),
    .clip_o(clip_sbase2));

  // ---- stages 3-4: the excess of a over d_lo, clamped to [0, d_span], as a word ----
  logic signed [W+3:0] exc3_q;
  logic signed [W+1:0] dspan3_q;
  logic signed [W+3:0] exc4_q;
  logic signed [W+3:0] clamp_w;
  always_comb begin
    clamp_w = exc3_q < 0 ? '0 : exc3_q;
    if (clamp_w > (W+4)'(dspan3_q)) clamp_w = (W+4)'(dspan3_q);
  end
  always_ff @(posedge clk_i) begin
    exc3_q <= (W+4)'(a_i) - (W+4)'(dlo2);
    dspan3_q <= dspan2;
    exc4_q <= clamp_w;  // exact: no saturation after the clamp (one carry chain in stage 4)
  end

  // ---- stages 5-10: z = zk * excess (ZW + 1 bits, signed, saturated) ----
  logic [B-1:0] en7;
  logic [EW-1:0] ee7;
  rheo_normalize #(.N(1), .InW(W+4), .B(B), .ShiftW(EW)) u_norm_exc (
    .clk_i(clk_i), .v_i(exc4_q), .mant_o(en7), .shift_o(ee7));
  logic [CoefW-1:0] zk7;
  rheo_delay #(.W(CoefW), .N(7)) u_zk_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CZk]), .q_o(zk7));
  logic signed [PW-1:0] zprod8_q;
  logic [6:0] zsb8_q;
  always_ff @(posedge clk_i) begin
    zprod8_q <= $signed(en7) * $signed(zk7[MantW-1:0]);
    // shift = (stored - Bias) - e, biased by MaxLeft = Bias + W + 4 - (B - 1) (e <= that - Bias)
    zsb8_q <= 7'(zk7[CoefW-1:MantW]) + 7'(W + 4 - (B - 1)) - 7'(ee7);
  end
  logic signed [ZW:0] z10;
  logic zclip10;
  rheo_round_shift #(.InW(PW), .OutW(ZW+1), .ShiftW(7), .MaxLeft(Bias + W + 4 - (B - 1))) u_z (
    .clk_i(clk_i), .v_i(zprod8_q), .sb_i(zsb8_q), .out_o(z10), .clip_o(zclip10));

  // ---- stages 11-14: qm = 2^-frac(z) in Q1.16, n = floor(z) ----
  logic [ZW-1:0] zc;
  assign zc = z10[ZW] ? '0 : z10[ZW-1:0];  // z < 0 counts as 0
  logic [TabB:0] e0_11_q, e1_11_q, e0_12_q, e0_13_q;
  logic [InterpB-1:0] t11_q, t12_q;
  logic [5:0] n11_q;
  logic zsat11_q;
  logic signed [B-1:0] diff12_q;
  logic signed [PW-1:0] ip13_q;
  logic signed [B-1:0] qm14_q;
  always_ff @(posedge clk_i) begin
    e0_11_q <= rheo_consts_pkg::exp2_table({1'b0, zc[FracZ-1 -: IdxB]});
    e1_11_q <= rheo_consts_pkg::exp2_table({1'b0, zc[FracZ-1 -: IdxB]} + (IdxB+1)'(1));
    t11_q <= zc[InterpB-1:0];
    n11_q <= zc[ZW-1:FracZ];
    zsat11_q <= zclip10 & ~z10[ZW];  // beyond the z word (a negative z is not a clip)
    diff12_q <= B'(e0_11_q) - B'(e1_11_q);
    e0_12_q <= e0_11_q;
    t12_q <= t11_q;
    ip13_q <= diff12_q * $signed({1'b0, (B-1)'(t12_q)});
    e0_13_q <= e0_12_q;
    qm14_q <= B'(e0_13_q) - B'((ip13_q + PW'(1 << (InterpB - 1))) >>> InterpB);
  end
  logic [5:0] n14;
  rheo_delay #(.W(6), .N(3)) u_n_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(n11_q), .q_o(n14));
  assign qm_o = qm14_q;
  assign n_o = n14;

  // ---- stages 15-18: s = s_base + s_c2 q ----
  logic [CoefW-1:0] sc2_14;
  rheo_delay #(.W(CoefW), .N(14)) u_sc2_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CSc2]), .q_o(sc2_14));
  logic signed [PW-1:0] sqprod15_q;
  logic [6:0] sqsb15_q;
  always_ff @(posedge clk_i) begin
    sqprod15_q <= qm14_q * $signed(sc2_14[MantW-1:0]);
    // shift = (stored - Bias) + (B - 2) + n - FracS, biased by MaxLeft = FracS - (B - 2) + Bias
    sqsb15_q <= 7'(sc2_14[CoefW-1:MantW]) + 7'(n14);
  end
  logic signed [SW-1:0] sq17;
  logic clip_sq17;
  rheo_round_shift #(.InW(PW), .OutW(SW), .ShiftW(7), .MaxLeft(FracS - (B - 2) + Bias)) u_sq (
    .clk_i(clk_i), .v_i(sqprod15_q), .sb_i(sqsb15_q), .out_o(sq17), .clip_o(clip_sq17));
  logic signed [SW-1:0] sbase17;
  rheo_delay #(.W(SW), .N(15)) u_sbase_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(sbase2), .q_o(sbase17));
  logic signed [SW:0] s_w;
  logic signed [SW-1:0] s18_q;
  logic clip_s18_q;
  always_comb s_w = (SW+1)'(sbase17) + (SW+1)'(sq17);
  always_ff @(posedge clk_i) begin
    clip_s18_q <= s_w[SW] ^ s_w[SW-1];
    if (s_w[SW] ^ s_w[SW-1]) s18_q <= {s_w[SW], {(SW-1){~s_w[SW]}}};
    else s18_q <= s_w[SW-1:0];
  end
  assign s_o = s18_q;

  always_comb begin
    for (int s = 0; s <= Last; s++) flag_at[s] = 1'b0;
    flag_at[2] = clip_sbase2;
    flag_at[11] = zsat11_q;
    flag_at[17] = clip_sq17;
    flag_at[18] = clip_s18_q;
  end
  logic unused;
  assign unused = ^{unused_clip_dlo, unused_clip_dspan};
endmodule
