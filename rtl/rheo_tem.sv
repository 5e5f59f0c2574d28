// Three-Element Module: one edge per clock (initiation interval 1), 3D. From both
// particles' positions x and displacements per step p, the Voigt length d, its natural
// length L and the edge's folded coefficients, it computes the force on the start
// particle f = T u (the end particle gets -f) and the new, clamped Voigt length:
//   r = x_e - x_s, dp = p_e - p_s, ds = d - L, y = rsqrt(r.r), l = r.r y, u = r y
//   ldot = u.dp, dd = beta ldot - alpha ds, T = kt ds + ct ldot
//   d' = clamp(d + dd, a_min l, a_max l)
// State words are W bits; every multiplier operand is B = OperandBits (18) bits, so each
// product is one MULT18X18: r and dp are block-normalised (one exponent per vector, the
// largest component sets it), ds, ldot, l, T (and m) are normalised words, u is a Q1.16
// operand, and each product's shift back to its format includes the operands' exponents.
// Rounding is to nearest at every narrowing, results saturate and raise sat_o.
// Latency: 40 clocks from valid_i to valid_o (rheo_consts_pkg::TemLatency). Register
// index t of each value (t = 0: input register):
//    1 r, dp, ds          4 r^, dp^ (rheo_normalize)   5 r^ squared   7 l2n = r^.r^
//   18 y (rheo_rsqrt)    19 m y, r^ y                 21 l, u         22 u dp^
//   24 u.dp^             26 ldot                      29 ldot^, ds^, l^
//   30 coefficient products                           32 scaled       33 dd, T (, dm)
//   34 dd >> 4 (, dm)    35 d + dd (, m + dm)         36 clamp, T^    37 T^ u
//   39 f (output registers).
// Each stage holds one multiplier (registered inputs and output), or one carry chain (at
// most ~45 bits; rounding chains span only the output bits) with a few LUT levels, or a
// barrel shift.
// Long delay lines (coefficients, d, operands waiting for y) are distributed RAM.
// Multipliers (all B x B): 3 (r.r) + 3 (rsqrt) + 1 (l) + 3 (u) + 3 (ldot)
// + 6 (coefficients) + 3 (T u) = 22.
// MaxwellArms = K (0..rheo_consts_pkg::MaxArms) adds K parallel Maxwell arms
// (rheo::hls::tem_edge<Fmt, K>): the edge carries each arm's extension m_j (m_i -> m_o,
// arm j at [j*W +: W]) and two more coefficients per arm (gamma_j, k2t_j). The arms'
// products need only m_j, so they run early, beside the length computation:
//    3 m_j^                4 m_j^ gamma_j, k2t_j m_j^    6 scaled
//    7-9 the exact sum of k2t_j m_j (a tree of pair sums, W + 3 bits for up to 8 arms),
//   which waits for stage 33: T = kt ds + ct ldot + sum (one saturation);
//   33 dm_j = ldot - m_j gamma_j    35 m_j' = m_j + dm_j.
// Same latency; +2 multipliers per arm (24 with one arm, 30 with four, 38 with eight). MaxwellArms = 0
// leaves m_i unused and m_o = 0.
// SeriesDamper = 1 adds the force-dependent series damper (rheo::hls::tem_edge<Fmt, K,
// true>): six more coefficients per material (d_lo, d_span, zk, s_base, s_c2, ka, after the
// base six), and rheo_damper turns ds into this edge's alpha, beta, kt, ct beside the
// length computation (stages 1-29), so the products of stage 30 read them; ka ldot (the
// arms' lead, which the damper does not scale) is a seventh product and a fourth term of T.
// Same latency; +13 multipliers.
// StrainHardening = 1 adds strain hardening (rheo::hls::tem_edge<Fmt, 0, false, true>):
// three more coefficients per material (hk, s_k, ct_h, after the damper's place), and
// rheo_harden turns l and L into this edge's alpha, beta, kt, ct and cth. It needs l (stage
// 21), so everything from the coefficient products on runs HardTemExtra stages later:
// stage t >= 30 below is t + HardTemExtra (latency 40 + HardTemExtra). cth ldot is a
// seventh product and a fourth term of T. +16 multipliers. With the damper as well, the
// damper's state follows the hardened spring's extension g |d - L|, so rheo_harden runs the
// damper's q and s after h (HardDamperTemExtra instead of HardTemExtra) and no rheo_damper
// is built; ka ldot and cth ldot are both terms of T. Hardening with arms needs the damper
// (ka, the arms' lead, is one of the damper's coefficients): that is the element with every
// effect.
// Mirrors rheo::hls::tem_edge.
module rheo_tem #(
  parameter int W = 32,      // state word width (rheo_consts_pkg::Width)
  parameter int CoefW = 24,  // packed coefficient {shift, mantissa}
  parameter int IdxW = 16,   // edge index carried alongside
  parameter int MaxwellArms = 0,  // parallel Maxwell arms, 0..rheo_consts_pkg::MaxArms
  parameter int SeriesDamper = 0, // force-dependent series damper (1) or not (0)
  parameter int StrainHardening = 0,  // strain hardening (1) or not (0)
  // 1: coef_i and mat_flags_i arrive LateCoefClocks after their edge's valid_i, when the
  // coefficient products need them, instead of with it (the sweep core looks its material
  // up late and saves the TEM's coefficient delay lines: 6 x 24 bits x 29 clocks of LUT
  // RAM). The three-element edge only (no arms, damper or hardening).
  parameter int LateCoef = 0,
  localparam int NumBaseCoef = rheo_consts_pkg::MaterialCoefs,
  localparam int NumDamperCoef = (SeriesDamper != 0) ? rheo_consts_pkg::DamperCoefs : 0,
  localparam int NumHardCoef = (StrainHardening != 0) ? rheo_consts_pkg::HardeningCoefs : 0,
  localparam int NumCoef = NumBaseCoef + NumDamperCoef + NumHardCoef +
                           rheo_consts_pkg::MaterialArmCoefs * MaxwellArms,
  localparam int ArmPorts = (MaxwellArms > 0) ? MaxwellArms : 1  // port words of m_i / m_o
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic              valid_i,
  input  logic [IdxW-1:0]   idx_i,
  input  logic [3*W-1:0]    xs_i,       // start position, {z, y, x}
  input  logic [3*W-1:0]    xe_i,       // end position
  input  logic [3*W-1:0]    ps_i,       // start displacement per step
  input  logic [3*W-1:0]    pe_i,       // end displacement per step
  input  logic [W-1:0]      d_i,        // Voigt length
  input  logic [W-1:0]      len_i,      // Voigt natural length L
  input  logic [ArmPorts*W-1:0] m_i,    // Maxwell-arm extensions, arm j at [j*W +: W]
  // {arms' {k2t_j, gamma_j} (arm K-1 first), [ct_h, s_k, hk,] [ka, s_c2, s_base, zk,
  //  d_span, d_lo,] a_max, a_min, ct, kt, beta, alpha}
  input  logic [NumCoef*CoefW-1:0] coef_i,
  input  logic [1:0]        mat_flags_i,// {clamp high enable, clamp low enable}
  output logic              valid_o,
  output logic [IdxW-1:0]   idx_o,
  output logic [3*W-1:0]    f_o,        // force on the start particle, {z, y, x}
  output logic [W-1:0]      d_o,        // new Voigt length
  output logic [ArmPorts*W-1:0] m_o,    // new Maxwell-arm extensions (0 without arms)
  output logic              sat_o,      // a result of this edge saturated
  output logic              degenerate_o// this edge has zero length
);
  localparam int B = rheo_consts_pkg::OperandBits;
  localparam int PW = 2 * B;  // product width
  localparam int FracX = rheo_consts_pkg::FracX;
  localparam int FracP = rheo_consts_pkg::FracP;
  localparam int FracU = rheo_consts_pkg::FracU;
  localparam int CoefMantBits = rheo_consts_pkg::CoefMantBits;
  localparam int CoefShiftBias = rheo_consts_pkg::CoefShiftBias;
  // Stages from the coefficient products on are HD later with hardening.
  localparam int HD = (StrainHardening == 0) ? 0 :
                     ((SeriesDamper != 0) ? rheo_consts_pkg::HardDamperTemExtra
                                          : rheo_consts_pkg::HardTemExtra);
  localparam int Last = rheo_consts_pkg::TemLatency - 1 + HD;  // index of the output stage
  // With the damper and hardening, ka ldot does not wait for the hardened coefficients: it
  // is computed at stages 30-32 and added to the arms' force at 33 (a lead that waits HD - 1
  // clocks), so T's sum has four terms rather than five.
  localparam bit PreLead = (SeriesDamper != 0) && (HD > 0);
  // With LateCoef: coef_i and mat_flags_i come this many clocks after valid_i (coef29 is
  // registered from coef_i one clock later, as the delay line's output would be).
  localparam int LateCoefClocks = rheo_consts_pkg::TemLateCoefClocks;
  localparam int EW = 6;  // normalisation exponents (< W - B + 2)
  localparam int CAlpha = 0, CBeta = 1, CKt = 2, CCt = 3, CAmin = 4, CAmax = 5;
  // Arm j's coefficients: CGamma + 2 j, CK2t + 2 j; the damper's ka: CKa; hardening's hk,
  // s_k, ct_h: CHk + 0, 1, 2.
  localparam int CHk = NumBaseCoef + NumDamperCoef;
  localparam int CGamma = NumBaseCoef + NumDamperCoef + NumHardCoef, CK2t = CGamma + 1;
  localparam int CKa = NumBaseCoef + 5;
  // Coefficient products of stage 30: the base six, ka ldot with the damper, cth ldot with
  // hardening.
  localparam int PKa = NumBaseCoef;
  localparam int PCth = NumBaseCoef + ((SeriesDamper != 0) ? 1 : 0);
  localparam int NumProd = PCth + ((StrainHardening != 0) ? 1 : 0);
  // Largest left shift of a coefficient product: the host keeps shift + extra >= 0, the
  // operand's exponent is at most W - (B - 1).
  localparam int CoefMaxLeft = W - (B - 1);

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_tem: W must equal rheo_consts_pkg::Width");
  end
  if (rheo_consts_pkg::TemLatency != 40) begin : g_latency_check
    $error("rheo_tem: the stage schedule below is for TemLatency = 40");
  end
  if (StrainHardening != 0 && SeriesDamper == 0 && MaxwellArms != 0) begin : g_hard_check
    $error("rheo_tem: strain hardening with arms needs the damper (its ka is the arms' lead)");
  end
  if (LateCoef != 0 && (MaxwellArms != 0 || SeriesDamper != 0 || StrainHardening != 0))
  begin : g_late_check
    $error("rheo_tem: late coefficients are for the three-element edge only");
  end
  if (MaxwellArms < 0 || MaxwellArms > rheo_consts_pkg::MaxArms) begin : g_arms_check
    $error("rheo_tem: MaxwellArms must be 0..rheo_consts_pkg::MaxArms");
  end
  if (NumBaseCoef != 6 || (SeriesDamper != 0 && NumDamperCoef != 6)) begin : g_coef_check
    $error("rheo_tem: the coefficients below are alpha, beta, kt, ct, a_min, a_max (and the damper's six)");
  end

  // Saturation of a (W+1)-bit sum to W bits: it clips iff the top two bits differ (a range
  // check without a comparator chain).
  function automatic logic clip(input logic signed [W:0] v);
    clip = v[W] ^ v[W-1];
  endfunction
  function automatic logic signed [W-1:0] sat(input logic signed [W:0] v);
    if (clip(v)) sat = {v[W], {(W-1){~v[W]}}};
    else sat = v[W-1:0];
  endfunction
  // The tension's three-term sum in W + 4 bits: fits iff the top five bits agree.
  function automatic logic clip4(input logic [4:0] top);  // bits W+3..W-1
    clip4 = !((&top) || !(|top));
  endfunction

  // ---- control pipeline: valid (reset), index, material flags, saturation ----
  logic [Last:0] v_q;  // packed: each pipeline below is one shift (no loop to unroll)
  logic [IdxW-1:0] idx0_q, idx20, idx_out;
  logic [1:0] mflags0_q, mflags35;
  logic [Last:0] sat_q;
  logic [Last:0] flag_at;  // clip flags visible in the registers of stage t

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      v_q <= '0;
    end else begin
      v_q <= {v_q[Last-1:0], valid_i};
    end
  end

  // ---- stage 0: input registers ----
  logic signed [W-1:0] xs_q [3], xe_q [3], ps_q [3], pe_q [3], d0_q, len_q;
  logic [ArmPorts*W-1:0] m0_q;
  logic [CoefW-1:0] coef0_q [NumCoef];
  always_ff @(posedge clk_i) begin
    idx0_q <= idx_i;
    mflags0_q <= mat_flags_i;
    for (int i = 0; i < 3; i++) begin
      xs_q[i] <= xs_i[i*W +: W];
      xe_q[i] <= xe_i[i*W +: W];
      ps_q[i] <= ps_i[i*W +: W];
      pe_q[i] <= pe_i[i*W +: W];
    end
    d0_q <= d_i;
    len_q <= len_i;
    m0_q <= m_i;
    for (int c = 0; c < NumCoef; c++) coef0_q[c] <= coef_i[c*CoefW +: CoefW];
  end
  rheo_delay #(.W(IdxW), .N(20)) u_idx_d1 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(idx0_q), .q_o(idx20));
  rheo_delay #(.W(IdxW), .N(Last - 20)) u_idx_d2 (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(idx20), .q_o(idx_out));
  if (LateCoef != 0) begin : g_mflags_late
    // registered LateCoefClocks after the edge: the clamp at stage 35 needs them 6 later
    rheo_delay #(.W(2), .N(35 - LateCoefClocks)) u_mflags_d (
      .clk_i(clk_i), .rst_ni(rst_ni), .d_i(mflags0_q), .q_o(mflags35));
  end else begin : g_mflags
    logic [1:0] mflags17;
    rheo_delay #(.W(2), .N(17)) u_mflags_d1 (
      .clk_i(clk_i), .rst_ni(rst_ni), .d_i(mflags0_q), .q_o(mflags17));
    rheo_delay #(.W(2), .N(18 + HD)) u_mflags_d2 (
      .clk_i(clk_i), .rst_ni(rst_ni), .d_i(mflags17), .q_o(mflags35));
  end

  // ---- stage 1: differences ----
  logic signed [W:0] r_w [3], dp_w [3], ds_w;
  logic signed [W-1:0] r1_q [3], dp1_q [3], ds1_q;
  logic clip1_q;
  always_comb begin
    for (int i = 0; i < 3; i++) begin
      r_w[i] = (W+1)'(xe_q[i]) - (W+1)'(xs_q[i]);
      dp_w[i] = (W+1)'(pe_q[i]) - (W+1)'(ps_q[i]);
    end
    ds_w = (W+1)'(d0_q) - (W+1)'(len_q);
  end
  always_ff @(posedge clk_i) begin
    clip1_q <= clip(ds_w) | clip(r_w[0]) | clip(r_w[1]) | clip(r_w[2]) | clip(dp_w[0]) |
               clip(dp_w[1]) | clip(dp_w[2]);
    for (int i = 0; i < 3; i++) begin
      r1_q[i] <= sat(r_w[i]);
      dp1_q[i] <= sat(dp_w[i]);
    end
    ds1_q <= sat(ds_w);
  end

  // ---- stages 2-4: dp as block-normalised operands ----
  logic [3*B-1:0] dpn4_flat;
  logic [EW-1:0] edp4;
  rheo_normalize #(.N(3), .InW(W), .B(B), .ShiftW(EW)) u_norm_dp (
    .clk_i(clk_i), .v_i({dp1_q[2], dp1_q[1], dp1_q[0]}), .mant_o(dpn4_flat), .shift_o(edp4));

  // ---- stages 2-21: l = |r|, u = r / |r| (rheo_length_direction) ----
  logic signed [W-1:0] l21;
  logic [3*B-1:0] u21_flat;
  logic signed [B-1:0] u21 [3];
  logic clip_lu21, deg21;
  rheo_length_direction #(.W(W), .B(B), .EW(EW)) u_len (
    .clk_i(clk_i), .rst_ni(rst_ni), .v_i({r1_q[2], r1_q[1], r1_q[0]}), .l_o(l21), .u_o(u21_flat),
    .clip_o(clip_lu21), .degenerate_o(deg21));
  always_comb for (int i = 0; i < 3; i++) u21[i] = u21_flat[i*B +: B];
  logic [Last:22] deg_q;
  always_ff @(posedge clk_i) deg_q <= {deg_q[Last-1:22], deg21};

  // ---- stages 22-26: ldot = u . dp^ 2^(edp - FracU) ----
  logic [3*B-1:0] dpn21_flat;
  logic [EW-1:0] edp23;
  rheo_delay #(.W(3*B), .N(17)) u_dpn_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(dpn4_flat), .q_o(dpn21_flat));
  rheo_delay #(.W(EW), .N(19)) u_edp_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(edp4), .q_o(edp23));
  logic signed [PW-1:0] ldp22_q [3];
  logic signed [PW:0] ls01_23_q, ldp2_23_q;
  logic signed [PW+1:0] lacc24_q;
  logic [6:0] lds24_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) ldp22_q[i] <= u21[i] * $signed(dpn21_flat[i*B +: B]);
    ls01_23_q <= (PW+1)'(ldp22_q[0]) + (PW+1)'(ldp22_q[1]);
    ldp2_23_q <= (PW+1)'(ldp22_q[2]);
    lacc24_q <= (PW+2)'(ls01_23_q) + (PW+2)'(ldp2_23_q);
    lds24_q <= 7'(FracU) - 7'(edp23);  // >= 1: edp <= W - (B-1) < FracU
  end
  logic signed [W-1:0] ldot26;
  logic clip_ldot26;
  rheo_round_shift #(.InW(PW+2), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_ldot (
    .clk_i(clk_i), .v_i(lacc24_q), .sb_i(lds24_q), .out_o(ldot26), .clip_o(clip_ldot26));

  // ---- stages 27-29: the coefficient operands ldot^, ds^, l^ ----
  logic signed [W-1:0] ds26, l26;
  rheo_delay #(.W(W), .N(25)) u_ds_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(ds1_q), .q_o(ds26));
  rheo_delay #(.W(W), .N(5)) u_l_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(l21), .q_o(l26));
  localparam int NumOp = 3;
  localparam int OpLdot = 0, OpDs = 1, OpL = 2;
  logic [W-1:0] op26 [NumOp];
  logic [B-1:0] opn29 [NumOp];
  logic [EW-1:0] ope29 [NumOp];
  always_comb begin
    op26[OpLdot] = ldot26;
    op26[OpDs] = ds26;
    op26[OpL] = l26;
  end
  for (genvar o = 0; o < NumOp; o++) begin : g_op
    rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm (
      .clk_i(clk_i), .v_i(op26[o]), .mant_o(opn29[o]), .shift_o(ope29[o]));
  end

  // ---- stage 30: coefficient products; stages 31-32: shifted back ----
  // this edge's coefficients: the material's, alpha..ct from the damper (and ka), or
  // alpha..ct and cth from the hardening unit; all at stage 29 (+ HD)
  logic [CoefW-1:0] coef29 [NumProd];
  logic clip_damper29, clip_hard29;  // (clip_hard29 is at stage 29 + HD)
  if (StrainHardening != 0) begin : g_hard
    // rheo_harden takes L, ds and the coefficients at its stage 0 = stage 17 and l at stage
    // 21 (its stage 4); its coefficients are ready at stage 17 + its latency = 29 + HD
    localparam int HardIn = 17;
    localparam int HardLast = (SeriesDamper != 0) ? 64 : 44;
    localparam int HardNumIn = (SeriesDamper != 0) ? 12 : 7;
    if (HardIn + HardLast != 29 + HD) begin : g_hard_latency_check
      $error("rheo_tem: HardTemExtra must be rheo_harden's latency less 12");
    end
    logic signed [W-1:0] len17, ds17;
    logic [HardNumIn*CoefW-1:0] hcoef0, hcoef17;
    logic [5*CoefW-1:0] hard29;
    always_comb begin
      for (int c = 0; c < 4; c++) hcoef0[c*CoefW +: CoefW] = coef0_q[c];
      for (int c = 0; c < 3; c++) hcoef0[(4+c)*CoefW +: CoefW] = coef0_q[CHk + c];
      // the damper's d_lo, d_span, zk, s_base, s_c2
      for (int c = 7; c < HardNumIn; c++) hcoef0[c*CoefW +: CoefW] = coef0_q[NumBaseCoef + c - 7];
    end
    rheo_delay #(.W(W), .N(HardIn)) u_len_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(len_q), .q_o(len17));
    rheo_delay #(.W(W), .N(HardIn - 1)) u_ds_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(ds1_q), .q_o(ds17));
    rheo_delay #(.W(HardNumIn*CoefW), .N(HardIn)) u_hcoef_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(hcoef0), .q_o(hcoef17));
    rheo_harden #(.W(W), .CoefW(CoefW), .SeriesDamper(SeriesDamper)) u_harden (
      .clk_i(clk_i), .len_i(len17), .ds_i(ds17), .coef_i(hcoef17), .l_i(l21), .coef_o(hard29),
      .clip_o(clip_hard29));
    for (genvar c = 0; c < 4; c++) begin : g_hard_coef
      assign coef29[c] = hard29[c*CoefW +: CoefW];
    end
    assign coef29[PCth] = hard29[4*CoefW +: CoefW];
    for (genvar c = 4; c < NumBaseCoef; c++) begin : g_coef_d
      rheo_delay #(.W(CoefW), .N(29 + HD)) u_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[c]), .q_o(coef29[c]));
    end
    if (SeriesDamper != 0) begin : g_ka
      // ka waits only for the undelayed operands (PreLead)
      rheo_delay #(.W(CoefW), .N(29)) u_ka_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[CKa]), .q_o(coef29[PKa]));
    end
    assign clip_damper29 = 1'b0;
  end else if (SeriesDamper != 0) begin : g_damper
    logic [12*CoefW-1:0] dcoef0;
    logic [4*CoefW-1:0] damped29;
    always_comb for (int c = 0; c < 12; c++) dcoef0[c*CoefW +: CoefW] = coef0_q[c];
    rheo_damper #(.W(W), .CoefW(CoefW)) u_damper (
      .clk_i(clk_i), .ds_i(ds1_q), .coef_i(dcoef0), .coef_o(damped29), .clip_o(clip_damper29));
    for (genvar c = 0; c < 4; c++) begin : g_damped
      assign coef29[c] = damped29[c*CoefW +: CoefW];
    end
    for (genvar c = 4; c < NumBaseCoef; c++) begin : g_coef_d
      rheo_delay #(.W(CoefW), .N(29)) u_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[c]), .q_o(coef29[c]));
    end
    rheo_delay #(.W(CoefW), .N(29)) u_ka_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[CKa]), .q_o(coef29[PKa]));
    assign clip_hard29 = 1'b0;
  end else begin : g_no_damper
    assign clip_damper29 = 1'b0;
    assign clip_hard29 = 1'b0;
    for (genvar c = 0; c < NumBaseCoef; c++) begin : g_coef_d
      if (LateCoef != 0) begin : g_late
        assign coef29[c] = coef0_q[c];  // registered LateCoefClocks after the edge
      end else begin : g_delay
        rheo_delay #(.W(CoefW), .N(29)) u_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[c]), .q_o(coef29[c]));
      end
    end
  end
  // the operands wait for the coefficients (HD clocks with hardening)
  logic [B-1:0] opnp [NumOp];
  logic [EW-1:0] opep [NumOp];
  for (genvar o = 0; o < NumOp; o++) begin : g_op_wait
    rheo_delay #(.W(B + EW), .N(HD)) u_d (
      .clk_i(clk_i), .rst_ni(rst_ni), .d_i({opn29[o], ope29[o]}), .q_o({opnp[o], opep[o]}));
  end
  // operand of each coefficient (products PKa and PCth are ka and cth) and the extra shift
  // of its format change
  function automatic int coef_operand(input int c);
    case (c)
      CBeta, CCt, PKa, PCth: coef_operand = OpLdot;
      CAlpha, CKt: coef_operand = OpDs;
      default: coef_operand = OpL;
    endcase
  endfunction
  function automatic int coef_extra(input int c);
    case (c)
      CAlpha: coef_extra = rheo_consts_pkg::ShiftAlpha;
      CBeta: coef_extra = rheo_consts_pkg::ShiftBeta;
      CKt: coef_extra = rheo_consts_pkg::ShiftKt;
      CCt, PKa, PCth: coef_extra = rheo_consts_pkg::ShiftCt;
      default: coef_extra = rheo_consts_pkg::ShiftClamp;
    endcase
  endfunction
  logic signed [PW-1:0] cprod30_q [NumProd];
  logic [6:0] cs30_q [NumProd];
  logic signed [W-1:0] cres32 [NumProd];
  logic cclip32 [NumProd];
  for (genvar c = 0; c < NumProd; c++) begin : g_coef
    // the operand: at stage 29 for ka ldot with PreLead, at 29 + HD for the others
    localparam bit Early = PreLead && c == PKa;
    logic [B-1:0] opn_c;
    logic [EW-1:0] ope_c;
    assign opn_c = Early ? opn29[coef_operand(c)] : opnp[coef_operand(c)];
    assign ope_c = Early ? ope29[coef_operand(c)] : opep[coef_operand(c)];
    always_ff @(posedge clk_i) begin
      cprod30_q[c] <= $signed(opn_c) * $signed(coef29[c][CoefMantBits-1:0]);
      // shift + extra - e, biased by CoefMaxLeft (>= 0: the host keeps shift + extra >= 0)
      cs30_q[c] <= 7'(coef29[c][CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
                   7'(coef_extra(c)) - 7'(ope_c);
    end
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_scale (
      .clk_i(clk_i), .v_i(cprod30_q[c]), .sb_i(cs30_q[c]), .out_o(cres32[c]),
      .clip_o(cclip32[c]));
  end

  // ---- stage 33: dd = beta ldot - alpha ds, T = kt ds + ct ldot + the arms' force ----
  logic signed [W+2:0] tarm_e32;  // exact sum of the arms' k2t_j m_j at stage 32 (0 without)
  logic signed [W+3:0] lead_l32;  // the arms' force (+ ka ldot with PreLead) at stage 32 + HD
  if (PreLead) begin : g_prelead
    // at most eight arms' words and ka ldot: exact in W + 4 bits
    logic signed [W+3:0] lead33_q;
    always_ff @(posedge clk_i) lead33_q <= (W+4)'(tarm_e32) + (W+4)'(cres32[PKa]);
    rheo_delay #(.W(W+4), .N(HD - 1)) u_lead_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(lead33_q), .q_o(lead_l32));
  end else begin : g_lead_wait
    logic signed [W+2:0] tarm_l32;
    rheo_delay #(.W(W+3), .N(HD)) u_tarm_d2 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(tarm_e32), .q_o(tarm_l32));
    assign lead_l32 = (W+4)'(tarm_l32);
  end
  logic signed [W-1:0] dd33_q, t33_q;
  logic clip33_q;
  logic signed [W+3:0] t_w;
  logic signed [W:0] dd_w;
  // T's terms: kt ds, ct ldot, the arms' words, and ka ldot (damper) and cth ldot
  // (hardening). At most eight arms' words (|sum| < 2^(W+2)) and four products below 2^(W-1)
  // each: T stays below 2^(W+3), so every sum below is exact in W + 4 bits (carries out of
  // the top bit are dropped: the true sum fits).
  localparam int NumTerms = 3 + ((SeriesDamper != 0 && !PreLead) ? 1 : 0) +
                            ((StrainHardening != 0) ? 1 : 0);
  logic [W+3:0] term [5];
  always_comb begin
    term[0] = (W+4)'(cres32[CKt]);
    term[1] = (W+4)'(cres32[CCt]);
    term[2] = lead_l32;
    term[3] = (SeriesDamper != 0 && !PreLead) ? (W+4)'(cres32[PKa])
                                              : (W+4)'(cres32[PCth < NumProd ? PCth : 0]);
    term[4] = (W+4)'(cres32[PCth < NumProd ? PCth : 0]);
  end
  // One carry-save step: three words to a sum word and a carry word (one LUT level each bit).
  function automatic logic [2*(W+4)-1:0] csa(input logic [W+3:0] a, input logic [W+3:0] b,
                                             input logic [W+3:0] c);
    csa = {{(a[W+2:0] & b[W+2:0]) | (a[W+2:0] & c[W+2:0]) | (b[W+2:0] & c[W+2:0]), 1'b0},
           a ^ b ^ c};
  endfunction
  // The terms through carry-save steps (one per term beyond two) and one carry chain.
  logic [W+3:0] red_s [NumTerms-1], red_c [NumTerms-1];
  always_comb begin
    {red_c[0], red_s[0]} = csa(term[0], term[1], term[2]);
    for (int k = 1; k < NumTerms - 2; k++)
      {red_c[k], red_s[k]} = csa(red_s[k-1], red_c[k-1], term[2 + k]);
    red_s[NumTerms-2] = red_s[NumTerms-3];
    red_c[NumTerms-2] = red_c[NumTerms-3];
  end
  always_comb begin
    dd_w = (W+1)'(cres32[CBeta]) - (W+1)'(cres32[CAlpha]);
    t_w = $signed(red_s[NumTerms-2]) + $signed(red_c[NumTerms-2]);
  end
  always_ff @(posedge clk_i) begin
    dd33_q <= sat(dd_w);
    if (clip4(t_w[W+3:W-1])) t33_q <= {t_w[W+3], {(W-1){~t_w[W+3]}}};
    else t33_q <= t_w[W-1:0];
    clip33_q <= clip(dd_w) | clip4(t_w[W+3:W-1]);
  end

  // ---- stages 34-36: T^ (operand of f) ----
  logic signed [B-1:0] tn36;
  logic [EW-1:0] et36;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_t (
    .clk_i(clk_i), .v_i(t33_q), .mant_o(tn36), .shift_o(et36));

  // ---- stages 34-36: d' = clamp(d + round(dd 2^-(FracP-FracX)), a_min l, a_max l) ----
  logic signed [W-1:0] d34, lo35, hi35;
  logic signed [W-1:0] d17;
  rheo_delay #(.W(W), .N(17)) u_d_d1 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(d0_q), .q_o(d17));
  rheo_delay #(.W(W), .N(17 + HD)) u_d_d2 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(d17), .q_o(d34));
  rheo_delay #(.W(W), .N(3)) u_lo_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(cres32[CAmin]), .q_o(lo35));
  rheo_delay #(.W(W), .N(3)) u_hi_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(cres32[CAmax]), .q_o(hi35));
  logic signed [W-1:0] ddr34_q, dnew35_q, dclamp36_q;
  logic signed [W:0] dnew_w;
  logic clip35_q;
  always_comb dnew_w = (W+1)'(d34) + (W+1)'(ddr34_q);
  always_ff @(posedge clk_i) begin
    ddr34_q <= W'(((W+1)'(dd33_q) + (W+1)'(1 << (FracP - FracX - 1))) >>> (FracP - FracX));
    dnew35_q <= sat(dnew_w);
    clip35_q <= clip(dnew_w);
    dclamp36_q <= dnew35_q;
    if (mflags35[0] && dnew35_q < lo35) dclamp36_q <= lo35;
    if (mflags35[1] && dnew35_q > hi35) dclamp36_q <= hi35;
  end

  // ---- stage 37: T^ u; stages 38-39: f = T^ u 2^(et - FracU) ----
  logic [3*B-1:0] u36_flat;
  rheo_delay #(.W(3*B), .N(15 + HD)) u_u_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i({u21[2], u21[1], u21[0]}), .q_o(u36_flat));
  logic signed [PW-1:0] fprod37_q [3];
  logic [6:0] fs37_q;
  logic signed [W-1:0] f39 [3];
  logic fclip39 [3];
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) fprod37_q[i] <= tn36 * $signed(u36_flat[i*B +: B]);
    fs37_q <= 7'(FracU) - 7'(et36);  // >= 1
  end
  for (genvar i = 0; i < 3; i++) begin : g_f
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_f (
      .clk_i(clk_i), .v_i(fprod37_q[i]), .sb_i(fs37_q), .out_o(f39[i]), .clip_o(fclip39[i]));
  end
  logic signed [W-1:0] d39;
  rheo_delay #(.W(W), .N(3)) u_dout_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(dclamp36_q), .q_o(d39));

  // ---- parallel Maxwell arms ----
  //   3 m_j^; 4 m_j^ gamma_j, k2t_j m_j^; 6 scaled; 7-9 the exact sum of k2t_j m_j;
  //   33 dm_j = ldot - m_j gamma_j; 34 dm_j >> (FracP - FracX); 35 m_j' = m_j + that
  logic clip_arm_at6, clip_arm_at33, clip_arm_at35;  // the arms' clip flags per stage
  if (MaxwellArms > 0) begin : g_arms
    localparam int K = MaxwellArms;
    localparam int Pairs = (K + 1) / 2, Quads = (K + 3) / 4;
    logic signed [W-1:0] tk6 [K];          // k2t_j m_j, scaled (stage 6)
    logic signed [W:0] tpair7_q [Pairs];   // sums of two arms
    logic signed [W+1:0] tquad8_q [Quads]; // sums of four
    logic signed [W+2:0] tarm9_q;          // all arms (at most eight)
    logic [K-1:0] clip6, clip_dm33, clip_m35;
    logic signed [W-1:0] ldot32;
    rheo_delay #(.W(W), .N(6 + HD)) u_ldot_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(ldot26), .q_o(ldot32));
    for (genvar j = 0; j < K; j++) begin : g_arm
      localparam int CG = CGamma + 2 * j, CK = CK2t + 2 * j;
      // m_j^ (stages 1-3) and the arm's two coefficients, which wait for it
      logic [B-1:0] mn3;
      logic [EW-1:0] me3;
      logic [CoefW-1:0] cg3, ck3;
      rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_m (
        .clk_i(clk_i), .v_i(m0_q[j*W +: W]), .mant_o(mn3), .shift_o(me3));
      rheo_delay #(.W(CoefW), .N(3)) u_cg_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[CG]), .q_o(cg3));
      rheo_delay #(.W(CoefW), .N(3)) u_ck_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(coef0_q[CK]), .q_o(ck3));
      // stage 4: the products; stages 5-6: shifted back (as the coefficient products above)
      logic signed [PW-1:0] gprod4_q, kprod4_q;
      logic [6:0] gs4_q, ks4_q;
      logic signed [W-1:0] mg6;
      logic clip_g6, clip_k6;
      always_ff @(posedge clk_i) begin
        gprod4_q <= $signed(mn3) * $signed(cg3[CoefMantBits-1:0]);
        kprod4_q <= $signed(mn3) * $signed(ck3[CoefMantBits-1:0]);
        gs4_q <= 7'(cg3[CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
                 7'(rheo_consts_pkg::ShiftGamma) - 7'(me3);
        ks4_q <= 7'(ck3[CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
                 7'(rheo_consts_pkg::ShiftK2t) - 7'(me3);
      end
      rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_scale_g (
        .clk_i(clk_i), .v_i(gprod4_q), .sb_i(gs4_q), .out_o(mg6), .clip_o(clip_g6));
      rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_scale_k (
        .clk_i(clk_i), .v_i(kprod4_q), .sb_i(ks4_q), .out_o(tk6[j]), .clip_o(clip_k6));
      assign clip6[j] = clip_g6 | clip_k6;
      // stage 33: dm_j = ldot - m_j gamma_j; 34: rounded to the X format; 35: m_j + dm_j
      logic signed [W-1:0] mg32, m34, dm33_q, dmr34_q, mnew35_q;
      logic signed [W:0] dm_w, mnew_w;
      logic clip_dm33_q, clip_m35_q;
      assign clip_dm33[j] = clip_dm33_q;
      assign clip_m35[j] = clip_m35_q;
      rheo_delay #(.W(W), .N(26 + HD)) u_mg_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(mg6), .q_o(mg32));
      logic signed [W-1:0] m17;  // two delay lines: one holds at most 33 clocks
      rheo_delay #(.W(W), .N(17)) u_m_d1 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(m0_q[j*W +: W]), .q_o(m17));
      rheo_delay #(.W(W), .N(17 + HD)) u_m_d2 (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(m17), .q_o(m34));
      always_comb begin
        dm_w = (W+1)'(ldot32) - (W+1)'(mg32);
        mnew_w = (W+1)'(m34) + (W+1)'(dmr34_q);
      end
      always_ff @(posedge clk_i) begin
        dm33_q <= sat(dm_w);
        clip_dm33_q <= clip(dm_w);
        dmr34_q <= W'(((W+1)'(dm33_q) + (W+1)'(1 << (FracP - FracX - 1))) >>> (FracP - FracX));
        mnew35_q <= sat(mnew_w);
        clip_m35_q <= clip(mnew_w);
      end
      rheo_delay #(.W(W), .N(4)) u_mout_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(mnew35_q), .q_o(m_o[j*W +: W]));
    end
    // stages 7-9: the arms' force, exact, one adder per stage (a pair fits W + 1 bits, four
    // arms W + 2, eight W + 3)
    always_ff @(posedge clk_i) begin
      for (int p = 0; p < Pairs; p++) begin
        if (2 * p + 1 < K) tpair7_q[p] <= (W+1)'(tk6[2*p]) + (W+1)'(tk6[2*p+1]);
        else tpair7_q[p] <= (W+1)'(tk6[2*p]);
      end
      for (int q = 0; q < Quads; q++) begin
        if (2 * q + 1 < Pairs) tquad8_q[q] <= (W+2)'(tpair7_q[2*q]) + (W+2)'(tpair7_q[2*q+1]);
        else tquad8_q[q] <= (W+2)'(tpair7_q[2*q]);
      end
      if (Quads > 1) tarm9_q <= (W+3)'(tquad8_q[0]) + (W+3)'(tquad8_q[Quads-1]);
      else tarm9_q <= (W+3)'(tquad8_q[0]);
    end
    rheo_delay #(.W(W+3), .N(23)) u_tarm_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(tarm9_q), .q_o(tarm_e32));
    assign clip_arm_at6 = |clip6;
    assign clip_arm_at33 = |clip_dm33;
    assign clip_arm_at35 = |clip_m35;
  end else begin : g_no_arms
    logic unused_m;
    assign unused_m = ^m0_q;
    assign tarm_e32 = '0;
    assign clip_arm_at6 = 1'b0;
    assign clip_arm_at33 = 1'b0;
    assign clip_arm_at35 = 1'b0;
    assign m_o = '0;
  end

  // ---- saturation flags: each clip joins the edge's flag in the stage where it is seen ----
  always_comb begin
    flag_at = '0;
    flag_at[1] = clip1_q;
    flag_at[6] = clip_arm_at6;
    flag_at[21] = clip_lu21;
    flag_at[26] = clip_ldot26;
    flag_at[29] = clip_damper29;
    flag_at[29 + HD] = flag_at[29 + HD] | clip_hard29;
    for (int c = 0; c < NumProd; c++) begin
      if (PreLead && c == PKa) flag_at[32] = flag_at[32] | cclip32[c];
      else flag_at[32 + HD] = flag_at[32 + HD] | cclip32[c];
    end
    flag_at[33 + HD] = clip33_q | clip_arm_at33;
    flag_at[35 + HD] = clip35_q | clip_arm_at35;
  end
  always_ff @(posedge clk_i) begin
    sat_q <= {sat_q[Last-1:0] | flag_at[Last-1:0], 1'b0};
  end

  assign valid_o = v_q[Last];
  assign idx_o = idx_out;
  assign f_o = {f39[2], f39[1], f39[0]};
  assign d_o = d39;
  assign sat_o = v_q[Last] & (sat_q[Last] | flag_at[Last] | fclip39[0] | fclip39[1] | fclip39[2]);
  assign degenerate_o = v_q[Last] & deg_q[Last];
endmodule
