// Strain hardening of the TEM (rheo::hls::hardened_coefs<Fmt, false>): this edge's
// coefficients from the material's (those of the unhardened spring) and its length l:
//   e = (l - L) / L                   (1/L: rheo_recip; l - L, e, e^2 as 18-bit operands)
//   h = hk e^2                        (an unsigned HardHBits word, HardFracH fraction bits;
//                                      beyond it clamped and flagged)
//   g = 1 + h, s = 1 + s_k h          (s: DamperFracS fraction bits, HardSBits wide)
//   alpha g / s, beta / s, kt g / s, ct / s, cth = ct_h h / s
// Each factor (g, h, 1/s and their products) is an 18-bit mantissa in [1/2, 1] and an
// exponent; a scaled coefficient keeps its 18-bit mantissa, a shift below the packed format
// is clamped and flagged, one above it gives up mantissa bits (cth falls to 0 with h).
// l is known late in the TEM (its stage 21), so this unit takes L and the coefficients four
// clocks before l: L's reciprocal is ready when l - L is normalised.
// Register index t of each value (len_i and coef_i are stage 0, l_i stage 4):
//    8 1/L (rheo_recip)    5 l - L     8 (l - L)^    9 (l - L)^ / L   12 e^
//   13 e^2                16 e^2^      17 hk e^2^    19 h as a word   20 h clamped
//   21 g = 1 + h          22 bit lengths             24 g and h as factors
//   25 s_k h              27 as a word 28 s          36 1/s (rheo_recip)
//   37 g/s, h/s           38 renormalised            39 coefficient products, shifts
//   40 shifts clamped     42 rounded (rheo_round_shift)  43 outputs
// Multipliers: 2 (1/L) + 1 (e) + 1 (e^2) + 1 (hk) + 1 (s_k) + 2 (1/s) + 2 (g/s, h/s)
// + 5 (coefficients) = 15.
module rheo_harden #(
  parameter int W = 32,
  parameter int CoefW = 24,
  localparam int NumIn = 7,   // {ct_h, s_k, hk, ct, kt, beta, alpha}
  localparam int NumOut = 5   // {cth, ct, kt, beta, alpha}
) (
  input  logic                     clk_i,
  input  logic signed [W-1:0]      len_i,   // L (stage 0)
  input  logic [NumIn*CoefW-1:0]   coef_i,  // stage 0
  input  logic signed [W-1:0]      l_i,     // the edge's length (stage 4)
  output logic [NumOut*CoefW-1:0]  coef_o,  // stage 43
  output logic                     clip_o   // a value saturated or a shift was clamped (43)
);
  localparam int B = rheo_consts_pkg::OperandBits;
  localparam int PW = 2 * B;
  localparam int MantW = rheo_consts_pkg::CoefMantBits;
  localparam int Bias = rheo_consts_pkg::CoefShiftBias;
  localparam int ShiftHi = (1 << rheo_consts_pkg::CoefShiftBits) - 1 - Bias;
  localparam int FracH = rheo_consts_pkg::HardFracH;
  localparam int HW = rheo_consts_pkg::HardHBits;
  localparam int FracS = rheo_consts_pkg::DamperFracS;
  localparam int SW = rheo_consts_pkg::HardSBits;
  localparam int EW = 6;
  localparam int CAlpha = 0, CBeta = 1, CKt = 2, CCt = 3, CHk = 4, CSk = 5, CCth = 6;
  localparam int OCth = 4;  // output index of cth (the others keep their input index)
  localparam int Last = 43;

  if (MantW != B) begin : g_width_check
    $error("rheo_harden: coefficient mantissas are 18-bit operands");
  end

  logic [CoefW-1:0] c0 [NumIn];
  always_comb for (int c = 0; c < NumIn; c++) c0[c] = coef_i[c*CoefW +: CoefW];
  // A packed coefficient's shift (stored - Bias), signed.
  function automatic logic signed [9:0] shift_of(input logic [CoefW-MantW-1:0] stored);
    shift_of = 10'(stored) - 10'(Bias);
  endfunction
  // Lower limit of a scaled coefficient's shift (hls::scaled_coef): the packed field, and
  // shift + extra >= 0.
  function automatic int shift_lo(input int o);
    int extra;
    case (o)
      CAlpha: extra = rheo_consts_pkg::ShiftAlpha;
      CBeta: extra = rheo_consts_pkg::ShiftBeta;
      CKt: extra = rheo_consts_pkg::ShiftKt;
      default: extra = rheo_consts_pkg::ShiftCt;  // ct and cth
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

  // ---- stages 1-8: 1/L = yl 2^-(B-2) 2^(1 - nbl) ----
  logic signed [B-1:0] yl8;
  logic [5:0] nbl8;
  logic lbad8;  // L <= 0 (the host never writes one): h = 0, flagged
  rheo_recip #(.InW(W), .NonPosNb(1)) u_recip_l (
    .clk_i(clk_i), .v_i(len_i), .y_o(yl8), .nb_o(nbl8), .nonpos_o(lbad8));

  // ---- stage 5: l - L; stages 6-8: normalised ----
  logic signed [W-1:0] len4;
  rheo_delay #(.W(W), .N(4)) u_len_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(len_i), .q_o(len4));
  logic signed [W:0] dl5_q;
  always_ff @(posedge clk_i) dl5_q <= (W+1)'(l_i) - (W+1)'(len4);
  logic signed [B-1:0] dm8;
  logic [EW-1:0] sd8;
  rheo_normalize #(.N(1), .InW(W+1), .B(B), .ShiftW(EW)) u_norm_dl (
    .clk_i(clk_i), .v_i(dl5_q), .mant_o(dm8), .shift_o(sd8));

  // ---- stage 9: (l - L)^ yl; stages 10-12: e^ = em 2^ee ----
  logic signed [PW-1:0] pe9_q;
  logic signed [7:0] ex9_q, ex12, ee13_q;  // exponents: ee = se + sd - (B-2) - (nbl-1)
  always_ff @(posedge clk_i) begin
    pe9_q <= dm8 * yl8;
    ex9_q <= 8'(sd8) - 8'(B - 2) - 8'(nbl8) + 8'd1;
  end
  rheo_delay #(.W(8), .N(3)) u_ex_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(ex9_q), .q_o(ex12));
  logic signed [B-1:0] em12;
  logic [EW-1:0] se12;
  rheo_normalize #(.N(1), .InW(PW), .B(B), .ShiftW(EW)) u_norm_e (
    .clk_i(clk_i), .v_i(pe9_q), .mant_o(em12), .shift_o(se12));

  // ---- stage 13: e^2 = e2 2^(2 ee); stages 14-16: normalised ----
  logic signed [PW-1:0] e2_13_q;
  always_ff @(posedge clk_i) begin
    e2_13_q <= em12 * em12;
    ee13_q <= ex12 + 8'(se12);
  end
  logic signed [B-1:0] e2m16;
  logic [EW-1:0] s2_16;
  logic signed [7:0] ee16;
  rheo_normalize #(.N(1), .InW(PW), .B(B), .ShiftW(EW)) u_norm_e2 (
    .clk_i(clk_i), .v_i(e2_13_q), .mant_o(e2m16), .shift_o(s2_16));
  rheo_delay #(.W(8), .N(3)) u_ee_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(ee13_q), .q_o(ee16));

  // ---- stage 17: hk e2^; stages 18-19: h = that 2^-(hk.shift - s2 - 2 ee - FracH) ----
  logic [CoefW-1:0] hk16;
  rheo_delay #(.W(CoefW), .N(16)) u_hk_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CHk]), .q_o(hk16));
  logic signed [PW-1:0] hprod17_q;
  logic [6:0] hsb17_q;
  logic signed [9:0] hsh_w;
  always_comb begin
    hsh_w = shift_of(hk16[CoefW-1:MantW]) - 10'(s2_16) - 10'(ee16) - 10'(ee16) - 10'(FracH);
    // beyond 2B every product rounds to 0, beyond -HW every non-zero one overflows
    if (hsh_w > 10'(2 * B)) hsh_w = 10'(2 * B);
    if (hsh_w < -10'(HW)) hsh_w = -10'(HW);
  end
  always_ff @(posedge clk_i) begin
    hprod17_q <= e2m16 * $signed(hk16[MantW-1:0]);
    hsb17_q <= 7'(hsh_w + 10'(HW));
  end
  logic signed [HW+1:0] hw19;
  logic unused_hclip;  // a saturated word is beyond HMax (or <= 0) below
  rheo_round_shift #(.InW(PW), .OutW(HW+2), .ShiftW(7), .MaxLeft(HW)) u_h (
    .clk_i(clk_i), .v_i(hprod17_q), .sb_i(hsb17_q), .out_o(hw19), .clip_o(unused_hclip));

  // ---- stage 20: h clamped to [0, 2^HW - 1]; 21: g = 1 + h; 22: bit lengths ----
  logic lbad19;
  rheo_delay #(.W(1), .N(11)) u_lbad_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(lbad8), .q_o(lbad19));
  localparam logic signed [HW+1:0] HMax = (HW+2)'((64'd1 << HW) - 1);
  logic [HW-1:0] h20_q, h21_q;
  logic hflag20_q;
  logic [HW:0] g21_q;
  always_ff @(posedge clk_i) begin
    if (lbad19 || hw19 <= 0) h20_q <= '0;
    else if (hw19 > HMax) h20_q <= HMax[HW-1:0];
    else h20_q <= hw19[HW-1:0];
    hflag20_q <= lbad19 || hw19 > HMax;
    g21_q <= (HW+1)'(h20_q) + (HW+1)'(1 << FracH);
    h21_q <= h20_q;
  end
  logic [5:0] ng22_q, nh22_q;
  logic [HW:0] g22_q;
  logic [HW-1:0] h22_q;
  logic [5:0] ng_w, nh_w;
  logic [HW:0] g_higher;
  logic [HW-1:0] h_higher;
  always_comb begin
    g_higher[HW] = 1'b0;
    for (int b = HW - 1; b >= 0; b--) g_higher[b] = g_higher[b+1] | g21_q[b+1];
    h_higher[HW-1] = 1'b0;
    for (int b = HW - 2; b >= 0; b--) h_higher[b] = h_higher[b+1] | h21_q[b+1];
    ng_w = '0;
    for (int b = 0; b <= HW; b++) ng_w = ng_w | ((g21_q[b] & ~g_higher[b]) ? 6'(b + 1) : 6'd0);
    nh_w = '0;
    for (int b = 0; b < HW; b++) nh_w = nh_w | ((h21_q[b] & ~h_higher[b]) ? 6'(b + 1) : 6'd0);
  end
  always_ff @(posedge clk_i) begin
    ng22_q <= ng_w;
    nh22_q <= nh_w;
    g22_q <= g21_q;
    h22_q <= h21_q;
  end

  // ---- stages 23-24: g and h as factors m 2^-(B-2) 2^e, m = round(word 2^-(n - (B-2))) ----
  logic signed [B-1:0] gm24, hm24;
  logic unused_gclip, unused_hmclip;  // m <= 2^(B-2): never clips
  rheo_round_shift #(.InW(HW+2), .OutW(B), .ShiftW(7), .MaxLeft(B - 2)) u_gm (
    .clk_i(clk_i), .v_i((HW+2)'(g22_q)), .sb_i(7'(ng22_q)), .out_o(gm24), .clip_o(unused_gclip));
  rheo_round_shift #(.InW(HW+2), .OutW(B), .ShiftW(7), .MaxLeft(B - 2)) u_hm (
    .clk_i(clk_i), .v_i((HW+2)'(h22_q)), .sb_i(7'(nh22_q)), .out_o(hm24), .clip_o(unused_hmclip));
  logic [5:0] ng24, nh24;
  rheo_delay #(.W(12), .N(2)) u_n_d (
    .clk_i(clk_i), .rst_ni(1'b1), .d_i({ng22_q, nh22_q}), .q_o({ng24, nh24}));

  // ---- stage 25: s_k h; stages 26-27: as a word (FracS); 28: s = 1 + that ----
  logic [CoefW-1:0] sk24;
  rheo_delay #(.W(CoefW), .N(24)) u_sk_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CSk]), .q_o(sk24));
  logic signed [PW-1:0] skprod25_q;
  logic [6:0] sksb25_q;
  logic signed [9:0] sksh_w;
  always_comb begin
    // s_k.shift + (B-2) - (nh - FracH) - FracS
    sksh_w = shift_of(sk24[CoefW-1:MantW]) + 10'(B - 2) - 10'(nh24) + 10'(FracH) - 10'(FracS);
    if (sksh_w > 10'(2 * B)) sksh_w = 10'(2 * B);
    if (sksh_w < -10'(SW)) sksh_w = -10'(SW);
  end
  always_ff @(posedge clk_i) begin
    skprod25_q <= hm24 * $signed(sk24[MantW-1:0]);
    sksb25_q <= 7'(sksh_w + 10'(SW));
  end
  logic signed [SW-1:0] sterm27;
  logic clip_sterm27;
  rheo_round_shift #(.InW(PW), .OutW(SW), .ShiftW(7), .MaxLeft(SW)) u_sterm (
    .clk_i(clk_i), .v_i(skprod25_q), .sb_i(sksb25_q), .out_o(sterm27), .clip_o(clip_sterm27));
  logic signed [SW:0] s_w;
  logic signed [SW-1:0] s28_q;
  logic clip_s28_q;
  always_comb s_w = (SW+1)'(sterm27) + (SW+1)'(64'd1 << FracS);
  always_ff @(posedge clk_i) begin
    clip_s28_q <= s_w[SW] ^ s_w[SW-1];
    if (s_w[SW] ^ s_w[SW-1]) s28_q <= {s_w[SW], {(SW-1){~s_w[SW]}}};
    else s28_q <= s_w[SW-1:0];
  end

  // ---- stages 29-36: 1/s = y 2^-(B-2) 2^(FracS + 1 - nb) ----
  logic signed [B-1:0] y36;
  logic [5:0] nb36;
  logic snp36;  // s <= 0 (never with the host's tables): flagged
  rheo_recip #(.InW(SW), .NonPosNb(FracS + 1)) u_recip_s (
    .clk_i(clk_i), .v_i(s28_q), .y_o(y36), .nb_o(nb36), .nonpos_o(snp36));

  // ---- stage 37: g/s, h/s; 38: renormalised (hls::factor_mul) ----
  logic signed [B-1:0] gm36, hm36;
  logic [5:0] ng36, nh36;
  rheo_delay #(.W(2*B), .N(12)) u_gh_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i({gm24, hm24}), .q_o({gm36, hm36}));
  rheo_delay #(.W(12), .N(12)) u_ngh_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i({ng24, nh24}), .q_o({ng36, nh36}));
  logic signed [PW-1:0] pg37_q, ph37_q;
  logic signed [9:0] ey37_q, eg37_q, eh37_q;  // exponents of 1/s, g/s, h/s
  logic hz37_q;
  logic signed [B-1:0] y37_q;
  always_ff @(posedge clk_i) begin
    pg37_q <= gm36 * y36;
    ph37_q <= hm36 * y36;
    ey37_q <= 10'(FracS + 1) - 10'(nb36);
    eg37_q <= 10'(ng36) - 10'(FracH) + 10'(FracS + 1) - 10'(nb36);
    eh37_q <= 10'(nh36) - 10'(FracH) + 10'(FracS + 1) - 10'(nb36);
    hz37_q <= hm36 == '0;
    y37_q <= y36;
  end
  // f = p 2^-(B-3) (exponent - 1) when p < 2^(2B-5), else p 2^-(B-2); rounded to nearest
  function automatic logic signed [B-1:0] renorm_mant(input logic signed [PW-1:0] p);
    if (p < PW'(64'd1 << (2 * B - 5))) renorm_mant = B'((p + PW'(1 << (B - 4))) >>> (B - 3));
    else renorm_mant = B'((p + PW'(1 << (B - 3))) >>> (B - 2));
  endfunction
  logic signed [B-1:0] fm38_q [3];  // factors of {h/s, g/s, 1/s}
  logic signed [9:0] fe38_q [3];
  localparam int FY = 0, FG = 1, FH = 2;
  always_ff @(posedge clk_i) begin
    fm38_q[FY] <= y37_q;
    fe38_q[FY] <= ey37_q;
    fm38_q[FG] <= renorm_mant(pg37_q);
    fe38_q[FG] <= eg37_q - ((pg37_q < PW'(64'd1 << (2 * B - 5))) ? 10'd1 : 10'd0);
    fm38_q[FH] <= hz37_q ? '0 : renorm_mant(ph37_q);
    fe38_q[FH] <= eh37_q - ((ph37_q < PW'(64'd1 << (2 * B - 5))) ? 10'd1 : 10'd0);
  end

  // ---- stage 39: the coefficients times their factor; 40: shifts; 41-42: rounded ----
  // alpha: g/s, beta: 1/s, kt: g/s, ct: 1/s, cth (from ct_h): h/s
  function automatic int factor_of_out(input int o);
    case (o)
      CAlpha, CKt: factor_of_out = FG;
      CBeta, CCt: factor_of_out = FY;
      default: factor_of_out = FH;  // cth
    endcase
  endfunction
  function automatic int input_of_out(input int o);
    input_of_out = (o == OCth) ? CCth : o;
  endfunction
  logic [CoefW-1:0] c19 [NumOut], c38 [NumOut];
  logic signed [PW-1:0] cp39_q [NumOut], cp40_q [NumOut];
  logic signed [9:0] sh39_q [NumOut];
  logic zero39_q [NumOut], zero40_q [NumOut], zero42 [NumOut];
  logic [6:0] rsb40_q [NumOut];
  logic signed [9:0] osh40_q [NumOut];
  logic [5:0] ost42 [NumOut];
  logic signed [MantW-1:0] m42 [NumOut];
  logic [NumOut-1:0] shclip_w;
  logic signed [9:0] shl_w [NumOut];
  logic signed [9:0] drop_w [NumOut];
  for (genvar o = 0; o < NumOut; o++) begin : g_out
    localparam int F = factor_of_out(o);
    // the coefficient waits 38 clocks (two lines: one holds at most 33)
    rheo_delay #(.W(CoefW), .N(19)) u_c_d1 (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[input_of_out(o)]), .q_o(c19[o]));
    rheo_delay #(.W(CoefW), .N(19)) u_c_d2 (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c19[o]), .q_o(c38[o]));
    always_ff @(posedge clk_i) begin
      cp39_q[o] <= $signed(c38[o][MantW-1:0]) * fm38_q[F];
      sh39_q[o] <= shift_of(c38[o][CoefW-1:MantW]) - fe38_q[F];
      zero39_q[o] <= fm38_q[F] == '0 || c38[o][MantW-1:0] == '0;
    end
    always_comb begin
      // below the format: clamped (and flagged); above it: mantissa bits dropped
      shl_w[o] = sh39_q[o] < 10'(shift_lo(o)) ? 10'(shift_lo(o)) : sh39_q[o];
      shclip_w[o] = !zero39_q[o] && sh39_q[o] < 10'(shift_lo(o));
      drop_w[o] = shl_w[o] - 10'(ShiftHi);
      if (drop_w[o] < 0) drop_w[o] = '0;
      if (drop_w[o] > 10'(2 * B)) drop_w[o] = 10'(2 * B);
    end
    always_ff @(posedge clk_i) begin
      cp40_q[o] <= cp39_q[o];
      rsb40_q[o] <= 7'(drop_w[o] + 10'(B - 2));
      osh40_q[o] <= shl_w[o] - drop_w[o];
      zero40_q[o] <= zero39_q[o];
    end
    logic unused_mclip;  // |mant| <= |c.mant|: never clips
    logic unused_out;
    assign unused_out = unused_mclip;
    rheo_round_shift #(.InW(PW), .OutW(MantW), .ShiftW(7), .MaxLeft(0)) u_mant (
      .clk_i(clk_i), .v_i(cp40_q[o]), .sb_i(rsb40_q[o]), .out_o(m42[o]), .clip_o(unused_mclip));
    logic [6:0] st_pack40;
    assign st_pack40 = {zero40_q[o], 6'(osh40_q[o] + 10'(Bias))};
    logic [6:0] st42;
    rheo_delay #(.W(7), .N(2)) u_st_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(st_pack40), .q_o(st42));
    assign zero42[o] = st42[6];
    assign ost42[o] = st42[5:0];
    // stage 43: packed; a zero factor or mantissa gives {ShiftHi, 0} (hls::scaled_coef)
    always_ff @(posedge clk_i) begin
      if (zero42[o]) coef_o[o*CoefW +: CoefW] <= {6'(ShiftHi + Bias), MantW'(0)};
      else coef_o[o*CoefW +: CoefW] <= {ost42[o], m42[o]};
    end
  end

  always_comb begin
    for (int s = 0; s <= Last; s++) flag_at[s] = 1'b0;
    flag_at[20] = hflag20_q;
    flag_at[27] = clip_sterm27;
    flag_at[28] = clip_s28_q;
    flag_at[36] = snp36;
    flag_at[39] = |shclip_w;
  end
  logic unused;
  assign unused = ^{unused_hclip, unused_gclip, unused_hmclip};
endmodule
