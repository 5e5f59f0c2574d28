// Strain hardening of the TEM (rheo::hls::hardened_coefs<Fmt, Damper>): this edge's
// coefficients from the material's (those of the unhardened spring) and its length l:
//   e = (l - L) / L                   (1/L: rheo_recip; l - L, e, e^2 as 18-bit operands)
//   h = hk e^2                        (an unsigned HardHBits word, HardFracH fraction bits;
//                                      beyond it clamped and flagged)
//   g = 1 + h, s = 1 + s_k h          (s: DamperFracS fraction bits, HardSBits wide)
//   alpha g / s, beta / s, kt g / s, ct / s, cth = ct_h h / s
// With SeriesDamper = 1 the force-dependent series damper acts on the hardened spring: its
// state follows the extension a = g |d - L| (rheo_damper_q, after h), q = 2^-z and
//   s = s_base + s_c2 q + s_k h;  alpha g / s, beta q / s, kt g q / s, ct q / s, cth h q / s.
// Each factor (g, h, q, 1/s and their products) is an 18-bit mantissa in [1/2, 1] and an
// exponent; a scaled coefficient keeps its 18-bit mantissa, a shift below the packed format
// is clamped and flagged, one above it gives up mantissa bits (cth falls to 0 with h).
// l is known late in the TEM (its stage 21), so this unit takes L and the coefficients four
// clocks before l: L's reciprocal is ready when l - L is normalised.
// Register index t of each value (len_i, ds_i and coef_i are stage 0, l_i stage 4):
//    8 1/L (rheo_recip)    5 l - L     8 (l - L)^    9 (l - L)^ / L   12 e^
//   13 e^2                16 e^2^      17 h's shift  18 hk e^2^       20 h as a word
//   21 h clamped, g = 1 + h    22 / 23 bit lengths of h / g    24 / 25 h / g as factors
//   23 s_k h's shift      24 clamped   25 s_k h      27 as a word
// Without the damper:
//   28 s     37 1/s (rheo_recip, two stages for s's bit length)  38 g/s, h/s
//   39 renormalised       40 coefficient products, shifts        41 shifts clamped
//   43 rounded            44 outputs
// With the damper (|d - L|^ at 4, waiting for h):
//   25 h^ |d - L|^         26 its shift clamped     28 h |d - L| as a word   29 a
//   41 q, 45 s_base + s_c2 q (rheo_damper_q)         46 s     55 1/s
//   56 q/s, g/s           57 renormalised          58 g q/s, h q/s           59 renormalised
//   60 coefficient products ... 64 outputs
// Multipliers: 2 (1/L) + 1 (e) + 1 (e^2) + 1 (hk) + 1 (s_k) + 2 (1/s) + 2 (g/s, h/s)
// + 5 (coefficients) = 15; with the damper 1 (h |d - L|) + 3 (rheo_damper_q) + 2 (q/s, g/s)
// + 2 (g q/s, h q/s) + 5 + the rest = 21.
module rheo_harden #(
  parameter int W = 32,
  parameter int CoefW = 24,
  parameter int SeriesDamper = 0,  // with the force-dependent series damper (1) or not (0)
  // {[s_c2, s_base, zk, d_span, d_lo,] ct_h, s_k, hk, ct, kt, beta, alpha}
  localparam int NumIn = (SeriesDamper != 0) ? 12 : 7,
  localparam int NumOut = 5,  // {cth, ct, kt, beta, alpha}
  // index of the output stage (rheo_consts_pkg::HardLatency / HardDamperLatency)
  localparam int Last = (SeriesDamper != 0) ? 64 : 44
) (
  input  logic                     clk_i,
  input  logic signed [W-1:0]      len_i,   // L (stage 0)
  input  logic signed [W-1:0]      ds_i,    // d - L (stage 0; read with the damper only)
  input  logic [NumIn*CoefW-1:0]   coef_i,  // stage 0
  input  logic signed [W-1:0]      l_i,     // the edge's length (stage 4)
  output logic [NumOut*CoefW-1:0]  coef_o,  // stage Last
  output logic                     clip_o   // a value saturated or a shift was clamped (Last)
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
  localparam int CDamper = 7;  // the damper's five, in the order rheo_damper_q reads them
  localparam int OCth = 4;  // output index of cth (the others keep their input index)
  // With the damper, s waits for the damper's q (DX stages) and the factors take a second
  // product (two stages): s at stage SS, 1/s at SY, the factors at SF.
  localparam int DX = (SeriesDamper != 0) ? 18 : 0;
  localparam int SS = 28 + DX, SY = SS + 9;
  localparam int SF = SY + ((SeriesDamper != 0) ? 4 : 2);
  if (Last != SF + 5) begin : g_last_check
    $error("rheo_harden: Last must be the stage schedule's output stage");
  end
  if (rheo_consts_pkg::HardTemExtra != 44 - 12 ||
      rheo_consts_pkg::HardDamperTemExtra != 64 - 12) begin : g_pkg_check
    $error("rheo_harden: rheo_consts_pkg's TEM extras must follow this unit's latency");
  end

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
  rheo_normalize #(.N(1), .InW(PW), .B(B), .ShiftW(EW)) u_norm_e2 (
    .clk_i(clk_i), .v_i(e2_13_q), .mant_o(e2m16), .shift_o(s2_16));
  // hk's shift less 2 ee and FracH, summed beside the normalisation (stage 14)
  logic [CoefW-1:0] hk13;
  logic [MantW-1:0] hkm17;
  rheo_delay #(.W(CoefW), .N(13)) u_hk_d1 (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CHk]), .q_o(hk13));
  rheo_delay #(.W(MantW), .N(4)) u_hk_d2 (.clk_i(clk_i), .rst_ni(1'b1), .d_i(hk13[MantW-1:0]), .q_o(hkm17));
  logic signed [9:0] hpart14_q, hpart16;
  always_ff @(posedge clk_i)  // biased by HW
    hpart14_q <= shift_of(hk13[CoefW-1:MantW]) - 10'(ee13_q) - 10'(ee13_q) - 10'(FracH) +
                 10'(HW);
  rheo_delay #(.W(10), .N(2)) u_hpart_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(hpart14_q), .q_o(hpart16));

  // ---- stage 17: e2^ and the shift hk.shift - s2 - 2 ee - FracH; 18: hk e2^, the shift
  //      clamped; 19-20: h = hk e2^ 2^-shift ----
  logic signed [B-1:0] e2m17_q;
  logic signed [9:0] hsh17_q;  // biased by HW
  always_ff @(posedge clk_i) begin
    e2m17_q <= e2m16;
    hsh17_q <= hpart16 - 10'(s2_16);
  end
  // beyond 2B every product rounds to 0, beyond -HW every non-zero one overflows
  logic signed [PW-1:0] hprod18_q;
  logic [6:0] hsb18_q;
  always_ff @(posedge clk_i) begin
    hprod18_q <= e2m17_q * $signed(hkm17);
    if (hsh17_q > 10'(2 * B + HW)) hsb18_q <= 7'(2 * B + HW);
    else if (hsh17_q < 0) hsb18_q <= '0;
    else hsb18_q <= 7'(hsh17_q);
  end
  logic signed [HW+1:0] hw20;
  logic unused_hclip;  // a saturated word is beyond HMax (or <= 0) below
  rheo_round_shift #(.InW(PW), .OutW(HW+2), .ShiftW(7), .MaxLeft(HW)) u_h (
    .clk_i(clk_i), .v_i(hprod18_q), .sb_i(hsb18_q), .out_o(hw20), .clip_o(unused_hclip));

  // ---- stage 21: h clamped to [0, 2^HW - 1] and g = 1 + h; bit lengths: h's at 22 (from
  //      the unclamped word, the clamp's two ends set apart), g's at 23 ----
  logic lbad20;
  rheo_delay #(.W(1), .N(12)) u_lbad_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(lbad8), .q_o(lbad20));
  localparam logic signed [HW+1:0] HMax = (HW+2)'((64'd1 << HW) - 1);
  logic [HW-1:0] h_w, h21_q, h22_q;
  logic hflag21_q, hzero21_q;
  logic [HW:0] g21_q, g22_q, g23_q;
  always_comb begin
    if (lbad20 || hw20 <= 0) h_w = '0;
    else if (hw20 > HMax) h_w = HMax[HW-1:0];
    else h_w = hw20[HW-1:0];
  end
  always_ff @(posedge clk_i) begin
    h21_q <= h_w;
    g21_q <= (HW+1)'(h_w) + (HW+1)'(1 << FracH);
    hflag21_q <= lbad20 || hw20 > HMax;
    hzero21_q <= lbad20 || hw20 <= 0;
    h22_q <= h21_q;
    g22_q <= g21_q;
    g23_q <= g22_q;
  end
  logic [5:0] nh_raw22, nh22, ng23;
  rheo_bitlen #(.InW(HW), .NW(6)) u_nh (.clk_i(clk_i), .v_i(hw20[HW-1:0]), .n_o(nh_raw22));
  logic hzero22_q, hbig22_q;
  always_ff @(posedge clk_i) begin
    hzero22_q <= hzero21_q;
    hbig22_q <= hflag21_q && !hzero21_q;
  end
  assign nh22 = hzero22_q ? 6'd0 : (hbig22_q ? 6'(HW) : nh_raw22);
  rheo_bitlen #(.InW(HW+1), .NW(6)) u_ng (.clk_i(clk_i), .v_i(g21_q), .n_o(ng23));

  // ---- stages 23-24 (h) and 24-25 (g): as factors m 2^-(B-2) 2^e, m = round(word
  //      2^-(n - (B-2))) ----
  logic signed [B-1:0] gm25, hm24;
  logic unused_gclip, unused_hmclip;  // m <= 2^(B-2): never clips
  rheo_round_shift #(.InW(HW+2), .OutW(B), .ShiftW(7), .MaxLeft(B - 2)) u_gm (
    .clk_i(clk_i), .v_i((HW+2)'(g23_q)), .sb_i(7'(ng23)), .out_o(gm25), .clip_o(unused_gclip));
  rheo_round_shift #(.InW(HW+2), .OutW(B), .ShiftW(7), .MaxLeft(B - 2)) u_hm (
    .clk_i(clk_i), .v_i((HW+2)'(h22_q)), .sb_i(7'(nh22)), .out_o(hm24), .clip_o(unused_hmclip));
  logic [5:0] nh24;
  rheo_delay #(.W(6), .N(2)) u_nh_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(nh22), .q_o(nh24));

  // ---- stage 25: s_k h; stages 26-27: as a word (FracS); 28: s = 1 + that ----
  // The product's shift s_k.shift + (B-2) - (nh - FracH) - FracS, biased by SW, from nh at
  // stage 22: summed at 23, clamped to [0, 2B + SW] at 24 (beyond 2B every product rounds
  // to 0, beyond -SW every non-zero one overflows).
  logic [CoefW-1:0] sk22;
  logic [MantW-1:0] skm24;
  rheo_delay #(.W(CoefW), .N(22)) u_sk_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[CSk]), .q_o(sk22));
  rheo_delay #(.W(MantW), .N(2)) u_skm_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(sk22[MantW-1:0]), .q_o(skm24));
  logic signed [9:0] sksh23_q;
  logic [6:0] sksb24_q;
  always_ff @(posedge clk_i) begin
    sksh23_q <= shift_of(sk22[CoefW-1:MantW]) - 10'(nh22) +
                10'(B - 2 + FracH - FracS + SW);
    if (sksh23_q > 10'(2 * B + SW)) sksb24_q <= 7'(2 * B + SW);
    else if (sksh23_q < 0) sksb24_q <= '0;
    else sksb24_q <= 7'(sksh23_q);
  end
  logic signed [PW-1:0] skprod25_q;
  logic [6:0] sksb25_q;
  always_ff @(posedge clk_i) begin
    skprod25_q <= hm24 * $signed(skm24);
    sksb25_q <= sksb24_q;
  end
  logic signed [SW-1:0] sterm27;
  logic clip_sterm27;
  rheo_round_shift #(.InW(PW), .OutW(SW), .ShiftW(7), .MaxLeft(SW)) u_sterm (
    .clk_i(clk_i), .v_i(skprod25_q), .sb_i(sksb25_q), .out_o(sterm27), .clip_o(clip_sterm27));

  // ---- with the damper, stages 1-28: a = g |ds| = |ds| + h |ds| (h |ds| held quietly to
  //      W + 2 bits, as hls::hardened_coefs), then stages 29-46: q (41) and s (45) of the
  //      damper for a (rheo_damper_q); without it q = 1 and s = 1 ----
  logic signed [SW-1:0] sdamp;  // s_base + s_c2 q at stage SS - 1
  logic signed [B-1:0] qm_y;    // q = qm 2^-(B-2) 2^-n at stage SY
  logic [5:0] n_y;
  logic clip_damp;              // at stage SS - 1
  if (SeriesDamper != 0) begin : g_damper
    // stage 1: |ds|; 2-4: normalised; they wait for h's factor (stage 24)
    logic signed [W:0] abs1_q;
    always_ff @(posedge clk_i) abs1_q <= ds_i[W-1] ? -((W+1)'(ds_i)) : (W+1)'(ds_i);
    logic signed [B-1:0] am4, am24;
    logic [EW-1:0] as4, as24;
    rheo_normalize #(.N(1), .InW(W+1), .B(B), .ShiftW(EW)) u_norm_abs (
      .clk_i(clk_i), .v_i(abs1_q), .mant_o(am4), .shift_o(as4));
    rheo_delay #(.W(B + EW), .N(20)) u_an_d (
      .clk_i(clk_i), .rst_ni(1'b1), .d_i({am4, as4}), .q_o({am24, as24}));
    // stage 25: h^ |ds|^ and its shift (B-2) - (nh - FracH) - e, biased by W + 2; 26: the
    // shift clamped to [-(W+2), 2B]; 27-28: as a word
    logic signed [PW-1:0] hd25_q, hd26_q;
    logic signed [9:0] hdsh25_q;
    logic [6:0] hdsb26_q;
    always_ff @(posedge clk_i) begin
      hd25_q <= hm24 * am24;
      hdsh25_q <= 10'(B - 2 + FracH + W + 2) - 10'(nh24) - 10'(as24);
      hd26_q <= hd25_q;
      if (hdsh25_q > 10'(2 * B + W + 2)) hdsb26_q <= 7'(2 * B + W + 2);
      else if (hdsh25_q < 0) hdsb26_q <= '0;
      else hdsb26_q <= 7'(hdsh25_q);
    end
    logic signed [W+1:0] hds28;
    logic unused_hdsclip;  // quiet: beyond W + 2 bits the damper's clamp gives the same q
    rheo_round_shift #(.InW(PW), .OutW(W+2), .ShiftW(7), .MaxLeft(W+2)) u_hds (
      .clk_i(clk_i), .v_i(hd26_q), .sb_i(hdsb26_q), .out_o(hds28), .clip_o(unused_hdsclip));
    logic signed [W:0] abs28;
    rheo_delay #(.W(W+1), .N(27)) u_abs_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(abs1_q), .q_o(abs28));
    logic signed [W+2:0] a29_q;
    always_ff @(posedge clk_i) a29_q <= (W+3)'(abs28) + (W+3)'(hds28);
    // rheo_damper_q: coefficients at its stage 0 = 27, a at its stage 2 = 29
    logic [5*CoefW-1:0] dc27;
    rheo_delay #(.W(5*CoefW), .N(27)) u_dc_d (
      .clk_i(clk_i), .rst_ni(1'b1), .d_i(coef_i[CDamper*CoefW +: 5*CoefW]), .q_o(dc27));
    logic signed [B-1:0] qm41;
    logic [5:0] n41;
    rheo_damper_q #(.W(W), .CoefW(CoefW), .AW(W+3), .SW(SW)) u_q (
      .clk_i(clk_i), .coef_i(dc27), .a_i(a29_q), .qm_o(qm41), .n_o(n41), .s_o(sdamp),
      .clip_o(clip_damp));
    rheo_delay #(.W(B + 6), .N(SY - 41)) u_q_d (
      .clk_i(clk_i), .rst_ni(1'b1), .d_i({qm41, n41}), .q_o({qm_y, n_y}));
    logic unused_damper;
    assign unused_damper = unused_hdsclip;
  end else begin : g_no_damper
    logic unused_ds;
    assign unused_ds = ^ds_i;
    assign sdamp = SW'(64'd1 << FracS);  // s_base + s_c2 = 1
    assign qm_y = B'(1 << (B - 2));
    assign n_y = '0;
    assign clip_damp = 1'b0;
  end

  // ---- stage SS: s = s_damper + s_k h (1 + s_k h without the damper) ----
  logic signed [SW-1:0] sterm_s;
  rheo_delay #(.W(SW), .N(SS - 1 - 27)) u_sterm_d (
    .clk_i(clk_i), .rst_ni(1'b1), .d_i(sterm27), .q_o(sterm_s));
  logic signed [SW:0] s_w;
  logic signed [SW-1:0] s_q;
  logic clip_s_q;
  always_comb s_w = (SW+1)'(sterm_s) + (SW+1)'(sdamp);
  always_ff @(posedge clk_i) begin
    clip_s_q <= s_w[SW] ^ s_w[SW-1];
    if (s_w[SW] ^ s_w[SW-1]) s_q <= {s_w[SW], {(SW-1){~s_w[SW]}}};
    else s_q <= s_w[SW-1:0];
  end

  // ---- stages SS+1 .. SY: 1/s = y 2^-(B-2) 2^(FracS + 1 - nb) ----
  logic signed [B-1:0] y_y;
  logic [5:0] nb_y;
  logic snp_y;  // s <= 0 (never with the host's tables): flagged
  rheo_recip #(.InW(SW), .NonPosNb(FracS + 1), .LenStages(2)) u_recip_s (
    .clk_i(clk_i), .v_i(s_q), .y_o(y_y), .nb_o(nb_y), .nonpos_o(snp_y));

  // ---- stages SY+1 .. SF: the factors (hls::factor_mul), each a product and a
  //      renormalisation: alpha g/s, beta and ct q/s, kt g q/s, cth h q/s ----
  logic signed [B-1:0] gm_y, hm_y;
  logic [5:0] ng_y, nh_y;
  rheo_delay #(.W(B), .N(SY - 25)) u_gm_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(gm25), .q_o(gm_y));
  rheo_delay #(.W(B), .N(SY - 24)) u_hm_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(hm24), .q_o(hm_y));
  rheo_delay #(.W(6), .N(SY - 23)) u_ng_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(ng23), .q_o(ng_y));
  rheo_delay #(.W(6), .N(SY - 24)) u_nh_d2 (.clk_i(clk_i), .rst_ni(1'b1), .d_i(nh24), .q_o(nh_y));
  // f = p 2^-(B-3) (exponent - 1) when p < 2^(2B-5), else p 2^-(B-2); rounded to nearest
  function automatic logic signed [B-1:0] renorm_mant(input logic signed [PW-1:0] p);
    if (p < PW'(64'd1 << (2 * B - 5))) renorm_mant = B'((p + PW'(1 << (B - 4))) >>> (B - 3));
    else renorm_mant = B'((p + PW'(1 << (B - 3))) >>> (B - 2));
  endfunction
  function automatic logic signed [9:0] renorm_exp(input logic signed [PW-1:0] p,
                                                   input logic signed [9:0] e);
    renorm_exp = e - ((p < PW'(64'd1 << (2 * B - 5))) ? 10'd1 : 10'd0);
  endfunction
  localparam int FA = 0, FB = 1, FK = 2, FC = 3;  // the factors of alpha, beta/ct, kt, cth
  logic signed [B-1:0] fm_q [4];
  logic signed [9:0] fe_q [4];
  // exponents of 1/s, g and h (factor = m 2^-(B-2) 2^e)
  logic signed [9:0] ey_w, eg_w, eh_w;
  always_comb begin
    ey_w = 10'(FracS + 1) - 10'(nb_y);
    eg_w = 10'(ng_y) - 10'(FracH);
    eh_w = 10'(nh_y) - 10'(FracH);
  end
  if (SeriesDamper != 0) begin : g_qfactors
    // SY+1: q/s, g/s; SY+2: renormalised; SY+3: g q/s, h q/s; SY+4: renormalised
    logic signed [PW-1:0] pqy1_q, pgy1_q, pgqy3_q, phqy3_q;
    logic signed [9:0] eqy1_q, egy1_q, eg1_q, eh1_q, eg2_q, eh2_q, egqy3_q, ehqy3_q;
    logic signed [B-1:0] gm1_q, hm1_q, gm2_q, hm2_q, fqy2_q, fgy2_q, fgy3_q, fqy3_q;
    logic signed [9:0] eqy2_q, egy2_q, egy3_q, eqy3_q;
    always_ff @(posedge clk_i) begin
      pqy1_q <= qm_y * y_y;
      pgy1_q <= gm_y * y_y;
      eqy1_q <= ey_w - 10'(n_y);
      egy1_q <= ey_w + eg_w;
      gm1_q <= gm_y;
      hm1_q <= hm_y;
      eg1_q <= eg_w;
      eh1_q <= eh_w;
      fqy2_q <= renorm_mant(pqy1_q);
      eqy2_q <= renorm_exp(pqy1_q, eqy1_q);
      fgy2_q <= renorm_mant(pgy1_q);
      egy2_q <= renorm_exp(pgy1_q, egy1_q);
      gm2_q <= gm1_q;
      hm2_q <= hm1_q;
      eg2_q <= eg1_q;
      eh2_q <= eh1_q;
      pgqy3_q <= gm2_q * fqy2_q;
      phqy3_q <= hm2_q * fqy2_q;
      egqy3_q <= eg2_q + eqy2_q;
      ehqy3_q <= eh2_q + eqy2_q;
      fgy3_q <= fgy2_q;
      egy3_q <= egy2_q;
      fqy3_q <= fqy2_q;
      eqy3_q <= eqy2_q;
      fm_q[FA] <= fgy3_q;
      fe_q[FA] <= egy3_q;
      fm_q[FB] <= fqy3_q;
      fe_q[FB] <= eqy3_q;
      fm_q[FK] <= renorm_mant(pgqy3_q);
      fe_q[FK] <= renorm_exp(pgqy3_q, egqy3_q);
      fm_q[FC] <= renorm_mant(phqy3_q);  // 0 with h = 0
      fe_q[FC] <= renorm_exp(phqy3_q, ehqy3_q);
    end
  end else begin : g_factors
    // SY+1: g/s, h/s; SY+2: renormalised (1/s is beta's and ct's factor as it is)
    logic signed [PW-1:0] pg1_q, ph1_q;
    logic signed [9:0] ey1_q, eg1_q, eh1_q;
    logic signed [B-1:0] y1_q;
    logic unused_q;
    assign unused_q = ^{qm_y, n_y};
    always_ff @(posedge clk_i) begin
      pg1_q <= gm_y * y_y;
      ph1_q <= hm_y * y_y;
      ey1_q <= ey_w;
      eg1_q <= ey_w + eg_w;
      eh1_q <= ey_w + eh_w;
      y1_q <= y_y;
      fm_q[FB] <= y1_q;
      fe_q[FB] <= ey1_q;
      fm_q[FA] <= renorm_mant(pg1_q);
      fe_q[FA] <= renorm_exp(pg1_q, eg1_q);
      fm_q[FK] <= renorm_mant(pg1_q);
      fe_q[FK] <= renorm_exp(pg1_q, eg1_q);
      fm_q[FC] <= renorm_mant(ph1_q);  // 0 with h = 0
      fe_q[FC] <= renorm_exp(ph1_q, eh1_q);
    end
  end

  // ---- stage SF+1 (c1 below): the coefficients times their factor; c2: shifts; c3-c4:
  //      rounded; c5 = Last: packed ----
  function automatic int factor_of_out(input int o);
    case (o)
      CAlpha: factor_of_out = FA;
      CKt: factor_of_out = FK;
      CBeta, CCt: factor_of_out = FB;
      default: factor_of_out = FC;  // cth
    endcase
  endfunction
  function automatic int input_of_out(input int o);
    input_of_out = (o == OCth) ? CCth : o;
  endfunction
  logic [CoefW-1:0] c0f [NumOut];
  logic signed [PW-1:0] cp1_q [NumOut], cp2_q [NumOut];
  logic signed [9:0] sh1_q [NumOut];
  logic zero1_q [NumOut], zero2_q [NumOut], zero4 [NumOut];
  logic [6:0] rsb2_q [NumOut];
  logic signed [9:0] osh2_q [NumOut];
  logic [5:0] ost4 [NumOut];
  logic signed [MantW-1:0] m4 [NumOut];
  logic [NumOut-1:0] shclip_w;
  logic signed [9:0] osh_w [NumOut];
  logic [6:0] rsb_w [NumOut];
  for (genvar o = 0; o < NumOut; o++) begin : g_out
    localparam int F = factor_of_out(o);
    // the coefficient waits for its factor
    rheo_delay #(.W(CoefW), .N(SF)) u_c_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(c0[input_of_out(o)]), .q_o(c0f[o]));
    always_ff @(posedge clk_i) begin
      cp1_q[o] <= $signed(c0f[o][MantW-1:0]) * fm_q[F];
      sh1_q[o] <= shift_of(c0f[o][CoefW-1:MantW]) - fe_q[F];
      zero1_q[o] <= fm_q[F] == '0 || c0f[o][MantW-1:0] == '0;
    end
    // Below the format the shift is clamped (and flagged); above it the product drops
    // drop = min(sh - hi, 2B) mantissa bits. The three comparisons with constants and the
    // candidate values run side by side, and one multiplexer picks (no chain of clamp,
    // subtract and clamp in one clock):
    //   sh < lo: shift lo, drop 0;  sh <= hi: sh, 0;  sh <= hi + 2B: hi, sh - hi;
    //   beyond: sh - 2B, 2B.
    localparam logic signed [9:0] Lo = 10'(shift_lo(o));
    localparam logic signed [9:0] Hi = 10'(ShiftHi);
    localparam logic signed [9:0] Hi2B = 10'(ShiftHi + 2 * B);
    always_comb begin
      shclip_w[o] = !zero1_q[o] && sh1_q[o] < Lo;
      if (sh1_q[o] < Lo) begin
        osh_w[o] = Lo;
        rsb_w[o] = 7'(B - 2);
      end else if (sh1_q[o] <= Hi) begin
        osh_w[o] = sh1_q[o];
        rsb_w[o] = 7'(B - 2);
      end else if (sh1_q[o] <= Hi2B) begin
        osh_w[o] = Hi;
        rsb_w[o] = 7'(sh1_q[o] - 10'(ShiftHi - (B - 2)));
      end else begin
        osh_w[o] = sh1_q[o] - 10'(2 * B);
        rsb_w[o] = 7'(3 * B - 2);
      end
    end
    always_ff @(posedge clk_i) begin
      cp2_q[o] <= cp1_q[o];
      rsb2_q[o] <= rsb_w[o];
      osh2_q[o] <= osh_w[o];
      zero2_q[o] <= zero1_q[o];
    end
    logic unused_mclip;  // |mant| <= |c.mant|: never clips
    logic unused_out;
    assign unused_out = unused_mclip;
    rheo_round_shift #(.InW(PW), .OutW(MantW), .ShiftW(7), .MaxLeft(0)) u_mant (
      .clk_i(clk_i), .v_i(cp2_q[o]), .sb_i(rsb2_q[o]), .out_o(m4[o]), .clip_o(unused_mclip));
    logic [6:0] st_pack2;
    assign st_pack2 = {zero2_q[o], 6'(osh2_q[o] + 10'(Bias))};
    logic [6:0] st4;
    rheo_delay #(.W(7), .N(2)) u_st_d (.clk_i(clk_i), .rst_ni(1'b1), .d_i(st_pack2), .q_o(st4));
    assign zero4[o] = st4[6];
    assign ost4[o] = st4[5:0];
    // stage Last: packed; a zero factor or mantissa gives {ShiftHi, 0} (hls::scaled_coef)
    always_ff @(posedge clk_i) begin
      if (zero4[o]) coef_o[o*CoefW +: CoefW] <= {6'(ShiftHi + Bias), MantW'(0)};
      else coef_o[o*CoefW +: CoefW] <= {ost4[o], m4[o]};
    end
  end

  always_comb begin
    for (int s = 0; s <= Last; s++) flag_at[s] = 1'b0;
    flag_at[21] = hflag21_q;
    flag_at[27] = clip_sterm27;
    flag_at[SS - 1] = flag_at[SS - 1] | clip_damp;
    flag_at[SS] = clip_s_q;
    flag_at[SY] = snp_y;
    flag_at[SF + 1] = |shclip_w;
  end
  logic unused;
  assign unused = ^{unused_hclip, unused_gclip, unused_hmclip};
endmodule
