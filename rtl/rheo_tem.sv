// Three-Element Module: one edge per clock (initiation interval 1), 3D. From both
// particles' positions x and displacements per step p, the Voigt length d, its natural
// length L and the edge's folded coefficients, it computes the force on the start
// particle f = T u (the end particle gets -f) and the new, clamped Voigt length:
//   r = x_e - x_s, dp = p_e - p_s, ds = d - L, y = rsqrt(r.r), l = r.r y, u = r y
//   ldot = u.dp, dd = beta ldot - alpha ds, T = kt ds + ct ldot
//   d' = clamp(d + dd, a_min l, a_max l)
// Rounding is to nearest at every narrowing, results saturate and raise sat_o.
// Latency: 18 clocks from valid_i to valid_o (1 input register, 3 stages to l2,
// 8 rsqrt stages, 6 stages to the clamped result). Mirrors rheo::hls::tem_edge.
// Multipliers: 3 (r.r) + 3 per Newton step x 2 + 1 (l) + 3 (u) + 3 (ldot)
// + 6 (coefficients) + 3 (T u) = 25.
// MaxwellArm = 1 adds the parallel Maxwell arm (rheo::hls::tem_edge<Fmt, true>): the
// edge carries the arm's extension m (m_i -> m_o) and two more coefficients (gamma, k2t):
//   stage 14: m gamma, k2t m;  stage 15: dm = ldot - m gamma, T = kt ds + ct ldot + k2t m;
//   stage 16: m' = m + dm.  Same latency; +2 multipliers (27). MaxwellArm = 0 builds
// exactly the baseline TEM (m_i ignored, m_o = 0).
module rheo_tem #(
  parameter int W = 32,      // state word width (rheo_consts_pkg::Width)
  parameter int CoefW = 24,  // packed coefficient {shift, mantissa}
  parameter int IdxW = 16,   // edge index carried alongside
  parameter int MaxwellArm = 0,  // 1: with the parallel Maxwell arm
  localparam int NumCoef = (MaxwellArm != 0) ? 8 : 6
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
  input  logic [W-1:0]      m_i,        // Maxwell-arm extension (MaxwellArm = 1)
  input  logic [NumCoef*CoefW-1:0] coef_i,  // {[k2t, gamma,] a_max, a_min, ct, kt, beta, alpha}
  input  logic [1:0]        mat_flags_i,// {clamp high enable, clamp low enable}
  output logic              valid_o,
  output logic [IdxW-1:0]   idx_o,
  output logic [3*W-1:0]    f_o,        // force on the start particle, {z, y, x}
  output logic [W-1:0]      d_o,        // new Voigt length
  output logic [W-1:0]      m_o,        // new Maxwell-arm extension (0 without the arm)
  output logic              sat_o,      // a result of this edge saturated
  output logic              degenerate_o// this edge has zero length
);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int FracX = rheo_consts_pkg::FracX;
  localparam int FracP = rheo_consts_pkg::FracP;
  localparam int FracU = rheo_consts_pkg::FracU;
  localparam int Last = rheo_consts_pkg::TemLatency - 1;  // index of the output stage
  localparam int CAlpha = 0, CBeta = 1, CKt = 2, CCt = 3, CAmin = 4, CAmax = 5;

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_tem: W must equal rheo_consts_pkg::Width");
  end

  function automatic logic signed [WideW-1:0] wide(input logic signed [W-1:0] v);
    wide = WideW'(v);
  endfunction
  function automatic logic clip(input logic signed [WideW-1:0] v);
    clip = rheo_consts_pkg::clips(v, W);
  endfunction
  function automatic logic signed [W-1:0] sat(input logic signed [WideW-1:0] v);
    sat = rheo_consts_pkg::sat_word(v);
  endfunction

  // ---- pipeline registers, indexed by stage ----
  logic v_q [Last+1];
  logic [IdxW-1:0] idx_q [Last+1];
  logic sat_q [Last+1];
  logic signed [W-1:0] xs_q [3], xe_q [3], ps_q [3], pe_q [3], len_q;
  logic signed [W-1:0] d_q [17];
  logic [CoefW-1:0] coef_q [15][NumCoef];
  logic [1:0] mflags_q [Last+1];
  logic signed [W-1:0] r_q [1:12][3];
  logic signed [W-1:0] dp_q [1:13][3];
  logic signed [W-1:0] ds_q [1:14];
  logic [63:0] sq_q [3];
  logic [67:0] l2_q;
  logic deg_q [12:Last];
  logic signed [W-1:0] l_q [12:14];
  logic signed [31:0] u_q [12:16][3];
  logic signed [W-1:0] ldot_q [13:14];
  logic signed [W-1:0] dd_beta_q, dd_alpha_q, t_spring_q, t_damper_q;
  logic signed [W-1:0] lo_q [14:16], hi_q [14:16];
  logic signed [W-1:0] dd_q, tension_q;
  logic signed [W-1:0] f_q [3], fout_q [3], dnew_q, dout_q;
  // Stage 15's tension sum and its clip flag: the baseline's, or with the Maxwell arm the
  // one that includes the arm's force (wires from g_arm / g_no_arm, so MaxwellArm = 0
  // leaves the baseline netlist as it was). sat_arm: the arm's own clip flags.
  logic signed [WideW-1:0] tension_sel_w;
  logic clip_tension15, sat_arm;

  logic [31:0] rs_mant, rs_y;
  logic signed [7:0] rs_k;
  logic rs_deg;
  rheo_rsqrt #(.L2W(68)) u_rsqrt (
    .clk_i       (clk_i),
    .l2_i        (l2_q),
    .mant_o      (rs_mant),
    .y_o         (rs_y),
    .k_o         (rs_k),
    .degenerate_o(rs_deg)
  );

  // ---- combinational stage logic ----
  logic signed [WideW-1:0] r_w [3], dp_w [3], ds_w, l_w, u_w [3], ldot_w;
  logic signed [WideW-1:0] dd_beta_w, dd_alpha_w, t_spring_w, t_damper_w, lo_w, hi_w;
  logic signed [WideW-1:0] dd_w, tension_w, f_w [3], dnew_w;
  logic signed [W-1:0] dclamp;
  logic clip1, clip12, clip13, clip14, clip15, clip16;
  always_comb begin
    clip1 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      r_w[i] = wide(xe_q[i]) - wide(xs_q[i]);
      dp_w[i] = wide(pe_q[i]) - wide(ps_q[i]);
      clip1 = clip1 | clip(r_w[i]) | clip(dp_w[i]);
    end
    ds_w = wide(d_q[0]) - wide(len_q);
    clip1 = clip1 | clip(ds_w);
    // stage 12: l = M Y 2^(k-45), u = r Y 2^-(k+15)
    l_w = rheo_consts_pkg::round_shift(WideW'($signed({1'b0, rs_mant})) * WideW'($signed({1'b0, rs_y})),
                                      45 - 32'(rs_k));
    clip12 = clip(l_w);
    for (int i = 0; i < 3; i++) begin
      u_w[i] = rheo_consts_pkg::round_shift(wide(r_q[11][i]) * WideW'($signed({1'b0, rs_y})),
                                           32'(rs_k) + 15);
      clip12 = clip12 | rheo_consts_pkg::clips(u_w[i], 32);
    end
    // stage 13: ldot = u . dp
    ldot_w = rheo_consts_pkg::round_shift(
        WideW'(u_q[12][0]) * wide(dp_q[12][0]) + WideW'(u_q[12][1]) * wide(dp_q[12][1]) +
        WideW'(u_q[12][2]) * wide(dp_q[12][2]), FracU);
    clip13 = clip(ldot_w);
    // stage 14: the six coefficient products
    dd_beta_w = rheo_consts_pkg::mul_coef_wide(ldot_q[13], coef_q[13][CBeta],
                                              rheo_consts_pkg::ShiftBeta);
    dd_alpha_w = rheo_consts_pkg::mul_coef_wide(ds_q[13], coef_q[13][CAlpha],
                                               rheo_consts_pkg::ShiftAlpha);
    t_spring_w = rheo_consts_pkg::mul_coef_wide(ds_q[13], coef_q[13][CKt],
                                               rheo_consts_pkg::ShiftKt);
    t_damper_w = rheo_consts_pkg::mul_coef_wide(ldot_q[13], coef_q[13][CCt],
                                               rheo_consts_pkg::ShiftCt);
    lo_w = rheo_consts_pkg::mul_coef_wide(l_q[13], coef_q[13][CAmin], rheo_consts_pkg::ShiftClamp);
    hi_w = rheo_consts_pkg::mul_coef_wide(l_q[13], coef_q[13][CAmax], rheo_consts_pkg::ShiftClamp);
    clip14 = clip(dd_beta_w) | clip(dd_alpha_w) | clip(t_spring_w) | clip(t_damper_w) |
             clip(lo_w) | clip(hi_w);
    // stage 15: dd and T
    dd_w = wide(dd_beta_q) - wide(dd_alpha_q);
    tension_w = wide(t_spring_q) + wide(t_damper_q);
    clip15 = clip(dd_w) | clip_tension15;
    // stage 16: f = T u, d + dd
    clip16 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      f_w[i] = rheo_consts_pkg::round_shift(wide(tension_q) * WideW'(u_q[15][i]), FracU);
      clip16 = clip16 | clip(f_w[i]);
    end
    dnew_w = wide(d_q[15]) + rheo_consts_pkg::round_shift(wide(dd_q), FracP - FracX);
    clip16 = clip16 | clip(dnew_w);
    // stage 17: length-ratio clamp
    dclamp = dnew_q;
    if (mflags_q[16][0] && dnew_q < lo_q[16]) dclamp = lo_q[16];
    if (mflags_q[16][1] && dnew_q > hi_q[16]) dclamp = hi_q[16];
  end

  // ---- valid pipeline (reset) ----
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      for (int s = 0; s <= Last; s++) v_q[s] <= 1'b0;
    end else begin
      v_q[0] <= valid_i;
      for (int s = 1; s <= Last; s++) v_q[s] <= v_q[s-1];
    end
  end

  // ---- datapath registers (no reset: qualified by v_q) ----
  always_ff @(posedge clk_i) begin
    // stage 0: input register
    idx_q[0] <= idx_i;
    sat_q[0] <= 1'b0;
    for (int i = 0; i < 3; i++) begin
      xs_q[i] <= xs_i[i*W +: W];
      xe_q[i] <= xe_i[i*W +: W];
      ps_q[i] <= ps_i[i*W +: W];
      pe_q[i] <= pe_i[i*W +: W];
    end
    d_q[0] <= d_i;
    len_q <= len_i;
    for (int c = 0; c < NumCoef; c++) coef_q[0][c] <= coef_i[c*CoefW +: CoefW];
    mflags_q[0] <= mat_flags_i;
    // pass-through of everything carried along
    for (int s = 1; s <= Last; s++) begin
      idx_q[s] <= idx_q[s-1];
      sat_q[s] <= sat_q[s-1];
      mflags_q[s] <= mflags_q[s-1];
    end
    for (int s = 1; s < 17; s++) d_q[s] <= d_q[s-1];
    for (int s = 1; s < 15; s++) coef_q[s] <= coef_q[s-1];
    for (int s = 2; s <= 12; s++) r_q[s] <= r_q[s-1];
    for (int s = 2; s <= 13; s++) dp_q[s] <= dp_q[s-1];
    for (int s = 2; s <= 14; s++) ds_q[s] <= ds_q[s-1];
    for (int s = 13; s <= Last; s++) deg_q[s] <= deg_q[s-1];
    for (int s = 13; s <= 16; s++) u_q[s] <= u_q[s-1];
    l_q[13] <= l_q[12];
    l_q[14] <= l_q[13];
    ldot_q[14] <= ldot_q[13];
    lo_q[15] <= lo_q[14];
    lo_q[16] <= lo_q[15];
    hi_q[15] <= hi_q[14];
    hi_q[16] <= hi_q[15];
    // stage 1: differences
    for (int i = 0; i < 3; i++) begin
      r_q[1][i] <= sat(r_w[i]);
      dp_q[1][i] <= sat(dp_w[i]);
    end
    ds_q[1] <= sat(ds_w);
    sat_q[1] <= clip1;
    // stage 2: squares; stage 3: l2 (stages 4..11 in the rsqrt unit)
    for (int i = 0; i < 3; i++) sq_q[i] <= 64'(r_q[1][i] * r_q[1][i]);
    l2_q <= 68'(sq_q[0]) + 68'(sq_q[1]) + 68'(sq_q[2]);
    // stage 12
    deg_q[12] <= rs_deg;
    l_q[12] <= sat(l_w);
    for (int i = 0; i < 3; i++) u_q[12][i] <= rheo_consts_pkg::sat_word(u_w[i]);
    sat_q[12] <= sat_q[11] | clip12;
    // stage 13
    ldot_q[13] <= sat(ldot_w);
    sat_q[13] <= sat_q[12] | clip13;
    // stage 14
    dd_beta_q <= sat(dd_beta_w);
    dd_alpha_q <= sat(dd_alpha_w);
    t_spring_q <= sat(t_spring_w);
    t_damper_q <= sat(t_damper_w);
    lo_q[14] <= sat(lo_w);
    hi_q[14] <= sat(hi_w);
    sat_q[14] <= sat_q[13] | clip14;
    // stage 15
    dd_q <= sat(dd_w);
    tension_q <= sat(tension_sel_w);
    sat_q[15] <= sat_q[14] | clip15;
    // stage 16
    for (int i = 0; i < 3; i++) f_q[i] <= sat(f_w[i]);
    dnew_q <= sat(dnew_w);
    sat_q[16] <= sat_q[15] | clip16;
    // stage 17
    dout_q <= dclamp;
    for (int i = 0; i < 3; i++) fout_q[i] <= f_q[i];
  end

  // ---- parallel Maxwell arm ----
  if (MaxwellArm != 0) begin : g_arm
    localparam int CGamma = 6, CK2t = 7;
    logic signed [W-1:0] m_q [16];
    logic signed [W-1:0] m_decay_q, t_arm_q, dm_q, mnew_q, mout_q;
    logic signed [WideW-1:0] m_decay_w, t_arm_w, dm_w, mnew_w;
    logic clip_arm14, clip_arm16;
    logic sat_arm_q [14:Last];  // aligned with sat_q
    // The baseline's two-term tension sum is replaced by the three-term one.
    logic unused_tension_w;
    assign unused_tension_w = ^tension_w;
    always_comb begin
      // stage 14: m gamma (X -> P) and k2t m (X -> F)
      m_decay_w = rheo_consts_pkg::mul_coef_wide(m_q[13], coef_q[13][CGamma],
                                                rheo_consts_pkg::ShiftGamma);
      t_arm_w = rheo_consts_pkg::mul_coef_wide(m_q[13], coef_q[13][CK2t],
                                              rheo_consts_pkg::ShiftK2t);
      clip_arm14 = clip(m_decay_w) | clip(t_arm_w);
      // stage 15: the arm's force joins T in one wide sum; dm = ldot - m gamma
      tension_sel_w = wide(t_spring_q) + wide(t_damper_q) + wide(t_arm_q);
      dm_w = wide(ldot_q[14]) - wide(m_decay_q);
      clip_tension15 = clip(tension_sel_w) | clip(dm_w);
      // stage 16: m + dm (P -> X)
      mnew_w = wide(m_q[15]) + rheo_consts_pkg::round_shift(wide(dm_q), FracP - FracX);
      clip_arm16 = clip(mnew_w);
    end
    always_ff @(posedge clk_i) begin
      m_q[0] <= m_i;
      for (int s = 1; s < 16; s++) m_q[s] <= m_q[s-1];
      m_decay_q <= sat(m_decay_w);
      t_arm_q <= sat(t_arm_w);
      dm_q <= sat(dm_w);
      mnew_q <= sat(mnew_w);
      mout_q <= mnew_q;
      sat_arm_q[14] <= clip_arm14;
      sat_arm_q[15] <= sat_arm_q[14];
      sat_arm_q[16] <= sat_arm_q[15] | clip_arm16;
      sat_arm_q[Last] <= sat_arm_q[16];
    end
    assign m_o = mout_q;
    assign sat_arm = sat_arm_q[Last];
  end else begin : g_no_arm
    logic unused_m_i;
    assign unused_m_i = ^m_i;
    assign tension_sel_w = tension_w;
    assign clip_tension15 = clip(tension_w);
    assign sat_arm = 1'b0;
    assign m_o = '0;
  end

  assign valid_o = v_q[Last];
  assign idx_o = idx_q[Last];
  assign f_o = {fout_q[2], fout_q[1], fout_q[0]};
  assign d_o = dout_q;
  assign sat_o = v_q[Last] & (sat_q[Last] | sat_arm);
  assign degenerate_o = v_q[Last] & deg_q[Last];
endmodule
