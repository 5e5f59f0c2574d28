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
//    2 |ds|               2-18 q (14) and s (18): rheo_damper_q, shared with rheo_harden
//   15 beta qm, kt qm, ct qm                            16 mantissas of beta q, kt q, ct q
//   19-26 y = 1/m, s = m 2^(nb-1) (rheo_recip)
//   27 mantissa products, shift sums                    28 rounded, shifts clamped, packed
//   29 outputs
// Multipliers: 3 (rheo_damper_q) + 3 (q) + 2 (reciprocal) + 4 (1/s) = 12.
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
  localparam int MantW = rheo_consts_pkg::CoefMantBits;
  localparam int Bias = rheo_consts_pkg::CoefShiftBias;
  localparam int TabB = rheo_consts_pkg::Exp2TableBits;
  localparam int FracS = rheo_consts_pkg::DamperFracS;
  localparam int SW = rheo_consts_pkg::DamperSBits;
  localparam int SeedB = rheo_consts_pkg::RecipSeedBits;
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

  // ---- stages 2-18: q = qm 2^-(B-2) 2^-n (14) and s (18) for a = |ds| (rheo_damper_q);
  //      stages 15-16: the mantissas of beta q, kt q, ct q ----
  logic signed [W:0] abs2_q;
  always_ff @(posedge clk_i) abs2_q <= ds_i[W-1] ? -((W+1)'(ds_i)) : (W+1)'(ds_i);
  logic signed [B-1:0] qm14_q;
  logic [5:0] n14;
  logic signed [SW-1:0] s18_q;
  logic clip_q18;
  rheo_damper_q #(.W(W), .CoefW(CoefW), .AW(W+1), .SW(SW)) u_q (
    .clk_i(clk_i), .coef_i({c0[CSc2], c0[CSbase], c0[CZk], c0[CDspan], c0[CDlo]}),
    .a_i(abs2_q), .qm_o(qm14_q), .n_o(n14), .s_o(s18_q), .clip_o(clip_q18));
  logic [CoefW-1:0] cq14 [3];  // beta, kt, ct
  for (genvar k = 0; k < 3; k++) begin : g_cq_d
    rheo_delay #(.W(CoefW), .N(14)) u_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CBeta + k]), .q_o(cq14[k]));
  end
  logic signed [PW-1:0] cqprod15_q [3];
  logic [5:0] n15_q;
  logic [5:0] cqs15_q [3];  // the coefficients' stored shifts
  logic signed [MantW-1:0] cqm16_q [3];
  logic [5:0] cqs16_q [3];
  always_ff @(posedge clk_i) begin
    n15_q <= n14;
    for (int k = 0; k < 3; k++) begin
      cqprod15_q[k] <= qm14_q * $signed(cq14[k][MantW-1:0]);
      cqs15_q[k] <= cq14[k][CoefW-1:MantW];
      // |mant qm| <= 2^17 2^16: the rounded mantissa fits (hls::damper_coefs' scale)
      cqm16_q[k] <= MantW'((cqprod15_q[k] + PW'(1 << (B - 3))) >>> (B - 2));
      cqs16_q[k] <= cqs15_q[k];
    end
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
    flag_at[18] = clip_q18;
    flag_at[26] = nonpos26;
    flag_at[27] = |shclip_w;
  end
  logic unused;
  assign unused = ^{clip28_q, coef_i[11*CoefW +: CoefW],
                    coef_i[4*CoefW +: 2*CoefW]};
endmodule
