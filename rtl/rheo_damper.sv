// Force-dependent series damper of the TEM (seed 000 §3.3): this edge's coefficients
// alpha, beta, kt, ct from the material's (those at c2 = c2_max) and the Voigt spring's
// extension ds = d - L:
//   z = zk * clamp(|ds| - d_lo, 0, d_span)   (log2 of c2_max / c2, DamperFracZ fraction bits)
//   q = 2^-z                                 (2^-f table over the top Exp2IndexBits fraction
//                                              bits, linear interpolation, times 2^-floor(z))
//   s = s_base + s_c2 q                      (c / c_ref, DamperFracS fraction bits)
//   1/s                                      (normalised, seed table, one Newton-Raphson step)
//   alpha / s, beta q / s, kt q / s, ct q / s (mantissas scaled, exponents into the shifts)
// The result depends on ds alone, which the TEM has at its stage 1, so this runs beside the
// length computation and delivers the coefficients to the TEM's coefficient products at
// stage 29: the TEM's latency does not change. Mirrors rheo::hls::damper_coefs.
// Register index t of each value (TEM stages; ds_i is stage 1, coef_i stage 0):
//    2 |ds|, d_lo and d_span as words, s_base as a word
//    3 |ds| - d_lo        4 clamped (W + 4 bits)        7 normalised
//    8 zk product         10 z                          11 z >= 0, table entries
//   12 entry difference   13 times the fraction         14 qm = 2^-frac(z)
//   15 s_c2 qm, beta qm, kt qm, ct qm                   16 mantissas of beta q, kt q, ct q
//   17 s_c2 q as a word   18 s                          19-26 y = 1/m, s = m 2^(nb-1)
//                                                        (rheo_recip)
//   27 mantissa products, shift sums                    28 rounded, shifts clamped, packed
//   29 outputs
// Multipliers: 1 (zk) + 1 (interpolation) + 4 (q) + 2 (reciprocal) + 4 (1/s) = 12.
module rheo_damper #(
  parameter int W = 32,
  parameter int CoefW = 24
) (
  input  logic              clk_i,
  input  logic signed [W-1:0] ds_i,         // d - L (stage 1)
  // {ka, s_c2, s_base, zk, d_span, d_lo, a_max, a_min, ct, kt, beta, alpha} (stage 0); ka,
  // a_min and a_max are not read here
  input  logic [12*CoefW-1:0] coef_i,
  output logic [4*CoefW-1:0]  coef_o,       // {ct, kt, beta, alpha} of this edge (stage 29)
  output logic              clip_o          // a value saturated or a shift was clamped (29)
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
  localparam int SW = rheo_consts_pkg::DamperSBits;
  localparam int SeedB = rheo_consts_pkg::RecipSeedBits;
  localparam int EW = 6;
  localparam int ShiftHi = (1 << rheo_consts_pkg::CoefShiftBits) - 1 - Bias;
  localparam int CAlpha = 0, CBeta = 1, CKt = 2, CCt = 3;
  localparam int CDlo = 6, CDspan = 7, CZk = 8, CSbase = 9, CSc2 = 10;
  localparam int Last = 29;

  if (B != 18 || TabB != B - 2 || SeedB != B - 2) begin : g_width_check
    $error("rheo_damper: the tables are Q1.16 operands of 18-bit products");
  end

  logic [CoefW-1:0] c0 [12];
  always_comb for (int c = 0; c < 12; c++) c0[c] = coef_i[c*CoefW +: CoefW];
  // Lower limit of a scaled coefficient's shift (hls::damped_shift): the packed field, and
  // shift + extra >= 0.
  function automatic int shift_lo(input int c);
    int extra;
    case (c)
      CAlpha: extra = rheo_consts_pkg::ShiftAlpha;
      CBeta: extra = rheo_consts_pkg::ShiftBeta;
      CKt: extra = rheo_consts_pkg::ShiftKt;
      CCt: extra = rheo_consts_pkg::ShiftCt;
      default: extra = 0;
    endcase
    shift_lo = extra > Bias ? -Bias : -extra;
  endfunction

  // ---- flags: each clip joins the edge's flag in the stage where it is seen ----
  logic flag_at [Last+1];
  logic fl_q [Last+1];
  always_ff @(posedge clk_i) begin
    fl_q[0] <= 1'b0;
    for (int s = 1; s <= Last; s++) fl_q[s] <= fl_q[s-1] | flag_at[s-1];
  end
  assign clip_o = fl_q[Last];

  // ---- stages 1-2: d_lo, d_span, s_base as words (coefficient mant 2^-(shift - frac)) ----
  // d_lo and d_span saturate quietly at W + 2 bits: beyond it the clamp below gives the
  // same result as the exact value would (hls::damper_coefs holds them the same way).
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

  // ---- stages 2-4: the excess of |ds| over d_lo, clamped to [0, d_span], as a word ----
  logic signed [W:0] abs2_q;
  logic signed [W+3:0] exc3_q;
  logic signed [W+1:0] dspan3_q;
  logic signed [W+3:0] exc4_q;
  logic signed [W+3:0] clamp_w;
  always_comb begin
    clamp_w = exc3_q < 0 ? '0 : exc3_q;
    if (clamp_w > (W+4)'(dspan3_q)) clamp_w = (W+4)'(dspan3_q);
  end
  always_ff @(posedge clk_i) begin
    abs2_q <= ds_i[W-1] ? -((W+1)'(ds_i)) : (W+1)'(ds_i);
    exc3_q <= (W+4)'(abs2_q) - (W+4)'(dlo2);
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

  // ---- stages 15-18: the q products; s = s_base + s_c2 q ----
  logic [CoefW-1:0] sc2_14, cq14 [3];  // s_c2; beta, kt, ct
  rheo_delay #(.W(CoefW), .N(14)) u_sc2_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CSc2]), .q_o(sc2_14));
  for (genvar k = 0; k < 3; k++) begin : g_cq_d
    rheo_delay #(.W(CoefW), .N(14)) u_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CBeta + k]), .q_o(cq14[k]));
  end
  logic signed [PW-1:0] sqprod15_q, cqprod15_q [3];
  logic [6:0] sqsb15_q;
  logic [5:0] n15_q;
  logic [5:0] cqs15_q [3];  // the coefficients' stored shifts
  logic signed [MantW-1:0] cqm16_q [3];
  logic [5:0] cqs16_q [3];
  always_ff @(posedge clk_i) begin
    sqprod15_q <= qm14_q * $signed(sc2_14[MantW-1:0]);
    // shift = (stored - Bias) + (B - 2) + n - FracS, biased by MaxLeft = FracS - (B - 2) + Bias
    sqsb15_q <= 7'(sc2_14[CoefW-1:MantW]) + 7'(n14);
    n15_q <= n14;
    for (int k = 0; k < 3; k++) begin
      cqprod15_q[k] <= qm14_q * $signed(cq14[k][MantW-1:0]);
      cqs15_q[k] <= cq14[k][CoefW-1:MantW];
      // |mant qm| <= 2^17 2^16: the rounded mantissa fits (hls::damper_coefs' scale)
      cqm16_q[k] <= MantW'((cqprod15_q[k] + PW'(1 << (B - 3))) >>> (B - 2));
      cqs16_q[k] <= cqs15_q[k];
    end
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

  // ---- stages 19-26: 1/s = y 2^-(B-2) 2^(FracS + 1 - nb) (rheo_recip: bit length, m,
  //      seed, y0 (2 - m y0)); s <= 0 gives y = 1 and nb = FracS + 1, flagged ----
  logic signed [B-1:0] y26_q;
  logic [5:0] nb26;
  logic nonpos26;
  rheo_recip #(.InW(SW), .NonPosNb(FracS + 1)) u_recip (
    .clk_i(clk_i), .v_i(s18_q), .y_o(y26_q), .nb_o(nb26), .nonpos_o(nonpos26));

  // ---- stages 27-29: the four coefficients times y, their shifts, packed ----
  logic [CoefW-1:0] alpha26;
  rheo_delay #(.W(CoefW), .N(26)) u_alpha_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CAlpha]), .q_o(alpha26));
  logic [3*MantW-1:0] cqm26_flat;
  logic [3*6-1:0] cqs26_flat;
  logic [5:0] n26;
  rheo_delay #(.W(3*MantW), .N(10)) u_cqm_d (
    .clk_i(clk_i), .rst_ni(1'b1), .d_i({cqm16_q[2], cqm16_q[1], cqm16_q[0]}), .q_o(cqm26_flat));
  rheo_delay #(.W(3*6), .N(10)) u_cqs_d (
    .clk_i(clk_i), .rst_ni(1'b1), .d_i({cqs16_q[2], cqs16_q[1], cqs16_q[0]}), .q_o(cqs26_flat));
  rheo_delay #(.W(6), .N(11)) u_n26_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(n15_q), .q_o(n26));
  logic signed [MantW-1:0] m26 [4];
  logic signed [8:0] sh26 [4];  // shift before 1/s: stored - Bias (+ n for the q-scaled)
  always_comb begin
    m26[CAlpha] = $signed(alpha26[MantW-1:0]);
    sh26[CAlpha] = 9'(alpha26[CoefW-1:MantW]) - 9'(Bias);
    for (int k = 0; k < 3; k++) begin
      m26[CBeta + k] = cqm26_flat[k*MantW +: MantW];
      sh26[CBeta + k] = 9'(cqs26_flat[k*6 +: 6]) - 9'(Bias) + 9'(n26);
    end
  end
  logic signed [PW-1:0] yprod27_q [4];
  logic signed [8:0] sh27_q [4];
  logic signed [MantW-1:0] m28_q [4];
  logic [5:0] st28_q [4];
  logic clip28_q;
  logic [3:0] shclip_w;
  logic signed [8:0] sh_lim [4];
  always_comb begin
    for (int c = 0; c < 4; c++) begin
      shclip_w[c] = 1'b0;
      sh_lim[c] = sh27_q[c];
      if (sh27_q[c] < 9'(shift_lo(c))) begin
        sh_lim[c] = 9'(shift_lo(c));
        shclip_w[c] = 1'b1;
      end else if (sh27_q[c] > 9'(ShiftHi)) begin
        sh_lim[c] = 9'(ShiftHi);
        shclip_w[c] = 1'b1;
      end
    end
  end
  always_ff @(posedge clk_i) begin
    for (int c = 0; c < 4; c++) begin
      yprod27_q[c] <= m26[c] * y26_q;
      sh27_q[c] <= sh26[c] + 9'(nb26) - 9'(FracS + 1);
      m28_q[c] <= MantW'((yprod27_q[c] + PW'(1 << (B - 3))) >>> (B - 2));
      st28_q[c] <= 6'(sh_lim[c] + 9'(Bias));
    end
    clip28_q <= |shclip_w;
  end
  always_ff @(posedge clk_i) begin
    for (int c = 0; c < 4; c++) coef_o[c*CoefW +: CoefW] <= {st28_q[c], m28_q[c]};
  end

  always_comb begin
    for (int s = 0; s <= Last; s++) flag_at[s] = 1'b0;
    flag_at[2] = clip_sbase2;
    flag_at[11] = zsat11_q;
    flag_at[17] = clip_sq17;
    flag_at[18] = clip_s18_q;
    flag_at[26] = nonpos26;
    flag_at[27] = |shclip_w;
  end
  logic unused;
  assign unused = ^{unused_clip_dlo, unused_clip_dspan, clip28_q, coef_i[11*CoefW +: CoefW],
                    coef_i[4*CoefW +: 2*CoefW]};
endmodule
