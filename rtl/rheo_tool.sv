// Tool unit: the contact of one particle per clock (initiation interval 1) with one rigid
// tool, a plane, a sphere or a cylinder, with Coulomb kinetic friction. From the particle's
// position x, displacement per step p and inverse mass minv and the tool's registers it
// computes the penalty force on the particle (a unilateral Voigt element between the
// particle and the tool's surface) and the friction against its slide along the surface:
//   r = x - c, dp = p - dc, along = a . r
//   plane: l = along, u = a;  sphere: r' = r;  cylinder: r' = r - along a
//   sphere, cylinder: y = rsqrt(r'.r'), l = r'.r' y, u = r' y   (rheo_length_direction)
//   ldot = u . dp, ds = l - reach, T = kt ds + ct ldot, F_n = -T
//   in reach: ds < 0, |along| <= half_length (cylinder), r' != 0 (sphere, cylinder)
//   dp_t = dp - ldot u - spin (a x u)     (spin: a turning cylinder's surface displacement)
//   l_t = |dp_t|, t = dp_t / l_t           (rheo_length_direction again)
//   F_t = min(mu F_n, l_t / minv)          (1/minv: rheo_recip; no cap for minv <= 0)
//   f = F_n u - F_t t when in reach and F_n > 0, else 0
// Every multiplier operand is B = OperandBits (18) bits, so each product is one MULT18X18:
// r, dp, r' and dp_t are block-normalised, along, ldot, ds, F_n, l_t and F_t normalised
// words, a, u, a x u and t Q1.16 operands. Rounding is to nearest at every narrowing;
// results saturate, and sat_o says that a result of a particle in reach saturated (a
// particle far from the tool may overflow its distance words, which only say it is out of
// reach). The cap l_t / minv saturates quietly: beyond the word, mu F_n is the smaller.
// The tool's registers (kind_i .. spin_i) are read at the stage that uses them: the core
// holds them constant while a pass runs.
// Latency: rheo_consts_pkg::ToolLatency = 84 clocks. Register index t of each value
// (t = 0: input register):
//    1 r, dp              4 r^, dp^ (rheo_normalize)   5 a r^         7 a . r^
//    9 along              12 along^                   13 along^ a    15 along a
//   16 r'                 19 r'^                      20 r'^ squared 22 l2n
//   33 y (rheo_rsqrt)     34 m y, r'^ y               36 l, u (the plane's along, a)
//   37 u dp^, ds, a x u products                      38 a x u difference
//   39 u . dp^            40 a x u                    41 ldot, spin (a x u) product
//   43 slip               44 ldot^, ds^               45 coefficient products, ldot^ u
//   47 scaled, ldot u     48 T, dp_t                  49 F_n         51 dp_t^
//   52 F_n^, dp_t^ squared                            53 F_n^ mu     54 l2t
//   55 f = F_n^ u, mu F_n 65 y_t (rheo_rsqrt)         66 m y_t, dp_t^ y_t
//   68 l_t, t             71 l_t^, 1/minv (rheo_recip from stage 63)
//   72 l_t^ / minv        74 cap                      75 F_t         78 F_t^
//   79 F_t^ t             81 F_t t                    82 f - F_t t
//   83 output registers (f gated by contact)
// Multipliers (all B x B): 3 (a . r) + 3 (along a) + 3 (r'.r') + 3 (rsqrt) + 1 (l)
// + 3 (u) + 3 (ldot) + 2 (coefficients) + 3 (F_n u) = 24 for the normal force, and
// 6 (a x u) + 3 (slip) + 3 (ldot u) + 3 (dp_t.dp_t) + 3 (rsqrt) + 1 (l_t) + 3 (t) + 1 (mu F_n)
// + 2 (rheo_recip) + 1 (cap) + 3 (F_t t) = 29 for friction: 53.
// Mirrors rheo::hls::tool_particle (hls/tool_contact.hpp).
module rheo_tool #(
  parameter int W = 32,      // state word width (rheo_consts_pkg::Width)
  parameter int CoefW = 24,  // packed coefficient {shift, mantissa}
  parameter int IdxW = 12,   // particle index carried alongside
  localparam int B = rheo_consts_pkg::OperandBits
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic              valid_i,
  input  logic [IdxW-1:0]   idx_i,
  input  logic [3*W-1:0]    x_i,          // particle position, {z, y, x}
  input  logic [3*W-1:0]    p_i,          // particle displacement per step
  input  logic [CoefW-1:0]  minv_i,       // particle's Fu dt^2 / (m Lu), packed
  // the tool's registers
  input  logic [1:0]        kind_i,       // rheo_consts_pkg::ToolOff/Plane/Sphere/Cylinder
  input  logic [3*W-1:0]    c_i,          // position now (X format)
  input  logic [3*W-1:0]    dc_i,         // displacement over the step (P format)
  input  logic [3*B-1:0]    a_i,          // unit normal or axis, Q1.(B-2) operands
  input  logic [W-1:0]      reach_i,      // eps (plane), radius + eps (sphere, cylinder)
  input  logic [W-1:0]      half_len_i,   // half the cylinder's length (X format)
  input  logic [CoefW-1:0]  kt_i,         // k, F per X
  input  logic [CoefW-1:0]  ct_i,         // c, F per P
  input  logic [CoefW-1:0]  mu_i,         // friction coefficient
  input  logic [CoefW-1:0]  spin_i,       // a cylinder's surface displacement, P LSBs
  output logic              valid_o,
  output logic [IdxW-1:0]   idx_o,
  output logic [3*W-1:0]    f_o,          // force on the particle, {z, y, x}
  output logic              contact_o,    // the tool pushes this particle
  output logic              sat_o
);
  localparam int PW = 2 * B;  // product width
  localparam int FracU = rheo_consts_pkg::FracU;
  localparam int CoefMantBits = rheo_consts_pkg::CoefMantBits;
  localparam int CoefShiftBias = rheo_consts_pkg::CoefShiftBias;
  localparam int Last = rheo_consts_pkg::ToolLatency - 1;  // index of the output stage
  localparam int EW = 6;  // normalisation exponents (< W - B + 2)
  // Largest left shift of a coefficient product: the host keeps shift + extra >= 0, the
  // operand's exponent is at most W - (B - 1).
  localparam int CoefMaxLeft = W - (B - 1);
  localparam logic [1:0] KPlane = 2'(rheo_consts_pkg::ToolPlane);
  localparam logic [1:0] KCylinder = 2'(rheo_consts_pkg::ToolCylinder);
  localparam logic [1:0] KOff = 2'(rheo_consts_pkg::ToolOff);

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_tool: W must equal rheo_consts_pkg::Width");
  end
  if (Last != 83) begin : g_latency_check
    $error("rheo_tool: the stage schedule below is for ToolLatency = 84");
  end

  function automatic logic clip(input logic signed [W:0] v);
    clip = v[W] ^ v[W-1];
  endfunction
  function automatic logic signed [W-1:0] sat(input logic signed [W:0] v);
    if (clip(v)) sat = {v[W], {(W-1){~v[W]}}};
    else sat = v[W-1:0];
  endfunction

  // ---- control pipeline: valid (reset), index, saturation ----
  logic [Last:0] v_q;
  logic [IdxW-1:0] idx_q, idx_out;
  logic [Last-1:0] sat_q;    // bit t: a clip of a stage < t
  logic [Last-2:0] flag_at;  // clip flags visible in the registers of stage t (f's: at 55)
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) v_q <= '0;
    else v_q <= {v_q[Last-1:0], valid_i};
  end
  rheo_delay #(.W(IdxW), .N(Last)) u_idx_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(idx_q), .q_o(idx_out));

  logic signed [B-1:0] a_op [3];
  always_comb for (int i = 0; i < 3; i++) a_op[i] = a_i[i*B +: B];

  // ---- stage 0: input registers ----
  logic signed [W-1:0] x_q [3], p_q [3];
  logic [CoefW-1:0] minv_q;
  always_ff @(posedge clk_i) begin
    idx_q <= idx_i;
    minv_q <= minv_i;
    for (int i = 0; i < 3; i++) begin
      x_q[i] <= x_i[i*W +: W];
      p_q[i] <= p_i[i*W +: W];
    end
  end

  // ---- stage 1: r = x - c, dp = p - dc ----
  logic signed [W:0] r_w [3], dp_w [3];
  logic signed [W-1:0] r1_q [3], dp1_q [3];
  logic clip1_q;
  always_comb begin
    for (int i = 0; i < 3; i++) begin
      r_w[i] = (W+1)'(x_q[i]) - (W+1)'($signed(c_i[i*W +: W]));
      dp_w[i] = (W+1)'(p_q[i]) - (W+1)'($signed(dc_i[i*W +: W]));
    end
  end
  always_ff @(posedge clk_i) begin
    clip1_q <= clip(r_w[0]) | clip(r_w[1]) | clip(r_w[2]) | clip(dp_w[0]) | clip(dp_w[1]) |
               clip(dp_w[2]);
    for (int i = 0; i < 3; i++) begin
      r1_q[i] <= sat(r_w[i]);
      dp1_q[i] <= sat(dp_w[i]);
    end
  end

  // ---- stages 2-4: r and dp as block-normalised operands ----
  logic [3*B-1:0] rn4_flat, dpn4_flat;
  logic [EW-1:0] er4, edp4;
  rheo_normalize #(.N(3), .InW(W), .B(B), .ShiftW(EW)) u_norm_r (
    .clk_i(clk_i), .v_i({r1_q[2], r1_q[1], r1_q[0]}), .mant_o(rn4_flat), .shift_o(er4));
  rheo_normalize #(.N(3), .InW(W), .B(B), .ShiftW(EW)) u_norm_dp (
    .clk_i(clk_i), .v_i({dp1_q[2], dp1_q[1], dp1_q[0]}), .mant_o(dpn4_flat), .shift_o(edp4));

  // ---- stages 5-9: along = a . r^ 2^(er - FracU) ----
  logic signed [PW-1:0] ar5_q [3];
  logic signed [PW:0] a01_6_q, a2_6_q;
  logic signed [PW+1:0] aacc7_q;
  logic [EW-1:0] er5_q, er6_q;
  logic [6:0] as7_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) ar5_q[i] <= a_op[i] * $signed(rn4_flat[i*B +: B]);
    a01_6_q <= (PW+1)'(ar5_q[0]) + (PW+1)'(ar5_q[1]);
    a2_6_q <= (PW+1)'(ar5_q[2]);
    aacc7_q <= (PW+2)'(a01_6_q) + (PW+2)'(a2_6_q);
    er5_q <= er4;
    er6_q <= er5_q;
    as7_q <= 7'(FracU) - 7'(er6_q);  // >= 1: er <= W - (B-1) < FracU
  end
  logic signed [W-1:0] along9;
  logic clip_along9;
  rheo_round_shift #(.InW(PW+2), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_along (
    .clk_i(clk_i), .v_i(aacc7_q), .sb_i(as7_q), .out_o(along9), .clip_o(clip_along9));

  // ---- stages 10-15: along a ----
  logic [B-1:0] an12;
  logic [EW-1:0] ean12;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_along (
    .clk_i(clk_i), .v_i(along9), .mant_o(an12), .shift_o(ean12));
  logic signed [PW-1:0] pr13_q [3];
  logic [6:0] ps13_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) pr13_q[i] <= $signed(an12) * a_op[i];
    ps13_q <= 7'(FracU) - 7'(ean12);
  end
  logic signed [W-1:0] proj15 [3];
  logic clip_proj15 [3];
  for (genvar i = 0; i < 3; i++) begin : g_proj
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_proj (
      .clk_i(clk_i), .v_i(pr13_q[i]), .sb_i(ps13_q), .out_o(proj15[i]), .clip_o(clip_proj15[i]));
  end

  // ---- stage 16: r' = r - along a (cylinder) or r ----
  logic [3*W-1:0] r15_flat;
  rheo_delay #(.W(3*W), .N(14)) u_r_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({r1_q[2], r1_q[1], r1_q[0]}), .q_o(r15_flat));
  logic signed [W:0] rp_w [3];
  logic signed [W-1:0] rp16_q [3];
  logic clip16_q;
  always_comb begin
    for (int i = 0; i < 3; i++) rp_w[i] = (W+1)'($signed(r15_flat[i*W +: W])) - (W+1)'(proj15[i]);
  end
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) rp16_q[i] <= (kind_i == KCylinder) ? sat(rp_w[i]) : r15_flat[i*W +: W];
    clip16_q <= (kind_i == KCylinder) && (clip(rp_w[0]) | clip(rp_w[1]) | clip(rp_w[2]));
  end

  // ---- stages 17-36: l = |r'|, u = r' / |r'| (rheo_length_direction) ----
  logic signed [W-1:0] l36;
  logic [3*B-1:0] u36_flat;
  logic signed [B-1:0] u36 [3];
  logic clip_lu36, deg36;
  rheo_length_direction #(.W(W), .B(B), .EW(EW)) u_len (
    .clk_i(clk_i), .rst_ni(rst_ni), .v_i({rp16_q[2], rp16_q[1], rp16_q[0]}), .l_o(l36),
    .u_o(u36_flat), .clip_o(clip_lu36), .degenerate_o(deg36));
  always_comb for (int i = 0; i < 3; i++) u36[i] = u36_flat[i*B +: B];
  // the plane's l and u: along and the normal
  logic signed [W-1:0] along36, l_sel36;
  logic signed [B-1:0] u_sel36 [3];
  rheo_delay #(.W(W), .N(27)) u_along_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(along9), .q_o(along36));
  always_comb begin
    l_sel36 = (kind_i == KPlane) ? along36 : l36;
    for (int i = 0; i < 3; i++) u_sel36[i] = (kind_i == KPlane) ? a_op[i] : u36[i];
  end

  // ---- stages 37-41: ldot = u . dp^ 2^(edp - FracU); ds = l - reach; in reach ----
  logic [3*B-1:0] dpn36_flat;
  logic [EW-1:0] edp38;
  rheo_delay #(.W(3*B), .N(32)) u_dpn_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(dpn4_flat), .q_o(dpn36_flat));
  rheo_delay #(.W(EW), .N(34)) u_edp_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(edp4), .q_o(edp38));
  logic signed [PW-1:0] ldp37_q [3];
  logic signed [PW:0] ls01_38_q, ldp2_38_q;
  logic signed [PW+1:0] lacc39_q;
  logic [6:0] lds39_q;
  logic signed [W:0] ds_w;
  logic signed [W-1:0] ds37_q;
  logic clip_ds37_q;
  logic ds_neg37_q, along_ok37_q, deg37_q, reach38_q;
  always_comb ds_w = (W+1)'(l_sel36) - (W+1)'($signed(reach_i));
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) ldp37_q[i] <= u_sel36[i] * $signed(dpn36_flat[i*B +: B]);
    ls01_38_q <= (PW+1)'(ldp37_q[0]) + (PW+1)'(ldp37_q[1]);
    ldp2_38_q <= (PW+1)'(ldp37_q[2]);
    lacc39_q <= (PW+2)'(ls01_38_q) + (PW+2)'(ldp2_38_q);
    lds39_q <= 7'(FracU) - 7'(edp38);
    ds37_q <= sat(ds_w);
    clip_ds37_q <= clip(ds_w);
    ds_neg37_q <= ds_w[W];  // the saturated word has the sum's sign
    along_ok37_q <= along36 <= $signed(half_len_i) && along36 >= -$signed(half_len_i);
    deg37_q <= deg36;
    reach38_q <= (kind_i != KOff) && ds_neg37_q && (kind_i != KCylinder || along_ok37_q) &&
                 (kind_i == KPlane || !deg37_q);
  end
  logic signed [W-1:0] ldot41;
  logic clip_ldot41;
  rheo_round_shift #(.InW(PW+2), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_ldot (
    .clk_i(clk_i), .v_i(lacc39_q), .sb_i(lds39_q), .out_o(ldot41), .clip_o(clip_ldot41));

  // ---- stages 42-47: ldot^, ds^; kt ds^, ct ldot^ shifted back ----
  logic signed [W-1:0] ds41;
  rheo_delay #(.W(W), .N(4)) u_ds_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(ds37_q), .q_o(ds41));
  logic [B-1:0] dsn44, ldn44;
  logic [EW-1:0] eds44, eld44;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_ds (
    .clk_i(clk_i), .v_i(ds41), .mant_o(dsn44), .shift_o(eds44));
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_ldot (
    .clk_i(clk_i), .v_i(ldot41), .mant_o(ldn44), .shift_o(eld44));
  logic signed [PW-1:0] kprod45_q, cprod45_q;
  logic [6:0] ks45_q, cs45_q;
  always_ff @(posedge clk_i) begin
    kprod45_q <= $signed(dsn44) * $signed(kt_i[CoefMantBits-1:0]);
    cprod45_q <= $signed(ldn44) * $signed(ct_i[CoefMantBits-1:0]);
    // shift + extra - e, biased by CoefMaxLeft (>= 0: the host keeps shift + extra >= 0)
    ks45_q <= 7'(kt_i[CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
              7'(rheo_consts_pkg::ShiftKt) - 7'(eds44);
    cs45_q <= 7'(ct_i[CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
              7'(rheo_consts_pkg::ShiftCt) - 7'(eld44);
  end
  logic signed [W-1:0] tk47, tc47;
  logic clip_tk47, clip_tc47;
  rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_kt (
    .clk_i(clk_i), .v_i(kprod45_q), .sb_i(ks45_q), .out_o(tk47), .clip_o(clip_tk47));
  rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_ct (
    .clk_i(clk_i), .v_i(cprod45_q), .sb_i(cs45_q), .out_o(tc47), .clip_o(clip_tc47));

  // ---- stage 48: T; stage 49: F_n = -T ----
  logic signed [W:0] t_w, fn_w;
  logic signed [W-1:0] t48_q, fn49_q;
  logic clip48_q, clip49_q;
  always_comb begin
    t_w = (W+1)'(tk47) + (W+1)'(tc47);
    fn_w = (W+1)'(0) - (W+1)'(t48_q);
  end
  always_ff @(posedge clk_i) begin
    t48_q <= sat(t_w);
    clip48_q <= clip(t_w);
    fn49_q <= sat(fn_w);
    clip49_q <= clip(fn_w);
  end

  // ---- stages 50-55: F_n^ u ----
  logic [B-1:0] fnn52;
  logic [EW-1:0] efn52;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_fn (
    .clk_i(clk_i), .v_i(fn49_q), .mant_o(fnn52), .shift_o(efn52));
  logic [3*B-1:0] u52_flat;
  rheo_delay #(.W(3*B), .N(16)) u_u_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({u_sel36[2], u_sel36[1], u_sel36[0]}), .q_o(u52_flat));
  logic signed [PW-1:0] fprod53_q [3];
  logic [6:0] fs53_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) fprod53_q[i] <= $signed(fnn52) * $signed(u52_flat[i*B +: B]);
    fs53_q <= 7'(FracU) - 7'(efn52);
  end
  logic signed [W-1:0] f55 [3];
  logic fclip55 [3];
  for (genvar i = 0; i < 3; i++) begin : g_f
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_f (
      .clk_i(clk_i), .v_i(fprod53_q[i]), .sb_i(fs53_q), .out_o(f55[i]), .clip_o(fclip55[i]));
  end

  // ---- friction: stages 37-40: a x u (Q1.16; the plane's is 0) ----
  logic signed [PW-1:0] xa37_q [3], xb37_q [3];
  logic signed [PW:0] xd38_q [3];
  logic signed [B-1:0] cross40 [3];
  logic clip_cross40 [3];
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) begin
      xa37_q[i] <= a_op[(i+1)%3] * u_sel36[(i+2)%3];
      xb37_q[i] <= a_op[(i+2)%3] * u_sel36[(i+1)%3];
      xd38_q[i] <= (PW+1)'(xa37_q[i]) - (PW+1)'(xb37_q[i]);
    end
  end
  for (genvar i = 0; i < 3; i++) begin : g_cross
    rheo_round_shift #(.InW(PW+1), .OutW(B), .ShiftW(7), .MaxLeft(0)) u_cross (
      .clk_i(clk_i), .v_i(xd38_q[i]), .sb_i(7'(FracU)), .out_o(cross40[i]),
      .clip_o(clip_cross40[i]));
  end

  // ---- stages 41-43: slip = spin (a x u), P format ----
  logic signed [PW-1:0] sp41_q [3];
  logic [6:0] ss41_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) sp41_q[i] <= cross40[i] * $signed(spin_i[CoefMantBits-1:0]);
    // shift + kSpin (>= 0: the host keeps it so)
    ss41_q <= 7'(spin_i[CoefW-1:CoefMantBits]) + 7'(rheo_consts_pkg::ShiftSpin - CoefShiftBias);
  end
  logic signed [W-1:0] slip43 [3];
  logic clip_slip43 [3];
  for (genvar i = 0; i < 3; i++) begin : g_slip
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_slip (
      .clk_i(clk_i), .v_i(sp41_q[i]), .sb_i(ss41_q), .out_o(slip43[i]), .clip_o(clip_slip43[i]));
  end

  // ---- stages 45-47: the normal part of dp, ldot^ u ----
  logic [3*B-1:0] u44_flat;
  rheo_delay #(.W(3*B), .N(8)) u_u44_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({u_sel36[2], u_sel36[1], u_sel36[0]}), .q_o(u44_flat));
  logic signed [PW-1:0] np45_q [3];
  logic [6:0] ns45_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) np45_q[i] <= $signed(ldn44) * $signed(u44_flat[i*B +: B]);
    ns45_q <= 7'(FracU) - 7'(eld44);
  end
  logic signed [W-1:0] normal47 [3];
  logic clip_normal47 [3];
  for (genvar i = 0; i < 3; i++) begin : g_normal
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_normal (
      .clk_i(clk_i), .v_i(np45_q[i]), .sb_i(ns45_q), .out_o(normal47[i]),
      .clip_o(clip_normal47[i]));
  end

  // ---- stage 48: dp_t = dp - ldot u - slip, saturated once ----
  logic [3*W-1:0] dp47_flat, slip47_flat;
  rheo_delay #(.W(3*W), .N(46)) u_dp47_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({dp1_q[2], dp1_q[1], dp1_q[0]}), .q_o(dp47_flat));
  rheo_delay #(.W(3*W), .N(4)) u_slip47_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({slip43[2], slip43[1], slip43[0]}), .q_o(slip47_flat));
  logic signed [W+1:0] dpt_w [3];
  logic signed [W-1:0] dpt48_q [3];
  logic dpt_fits [3];
  logic clip_dpt48_q;
  always_comb begin
    for (int i = 0; i < 3; i++) begin
      dpt_w[i] = (W+2)'($signed(dp47_flat[i*W +: W])) - (W+2)'(normal47[i]) -
                 (W+2)'($signed(slip47_flat[i*W +: W]));
      // fits iff bits W+1..W-1 are equal
      dpt_fits[i] = (&dpt_w[i][W+1:W-1]) | ~(|dpt_w[i][W+1:W-1]);
    end
  end
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++)
      dpt48_q[i] <= dpt_fits[i] ? dpt_w[i][W-1:0] : {dpt_w[i][W+1], {(W-1){~dpt_w[i][W+1]}}};
    clip_dpt48_q <= ~(dpt_fits[0] & dpt_fits[1] & dpt_fits[2]);
  end

  // ---- stages 49-68: l_t = |dp_t|, t = dp_t / |dp_t| (rheo_length_direction) ----
  logic signed [W-1:0] lt68;
  logic [3*B-1:0] t68_flat;
  logic signed [B-1:0] t68 [3];
  logic clip_lt68, deg_t68;
  rheo_length_direction #(.W(W), .B(B), .EW(EW)) u_len_t (
    .clk_i(clk_i), .rst_ni(rst_ni), .v_i({dpt48_q[2], dpt48_q[1], dpt48_q[0]}), .l_o(lt68),
    .u_o(t68_flat), .clip_o(clip_lt68), .degenerate_o(deg_t68));
  always_comb for (int i = 0; i < 3; i++) t68[i] = t68_flat[i*B +: B];

  // ---- stages 53-55: mu F_n (F format) ----
  logic signed [PW-1:0] mprod53_q;
  logic [6:0] ms53_q;
  always_ff @(posedge clk_i) begin
    mprod53_q <= $signed(fnn52) * $signed(mu_i[CoefMantBits-1:0]);
    ms53_q <= 7'(mu_i[CoefW-1:CoefMantBits]) + 7'(CoefMaxLeft - CoefShiftBias) +
              7'(rheo_consts_pkg::ShiftMu) - 7'(efn52);
  end
  logic signed [W-1:0] mufn55;
  logic clip_mufn55;
  rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(CoefMaxLeft)) u_mu (
    .clk_i(clk_i), .v_i(mprod53_q), .sb_i(ms53_q), .out_o(mufn55), .clip_o(clip_mufn55));

  // ---- stages 64-74: the cap l_t / minv (F format) ----
  // 1/minv: minv = mant 2^-shift, mant = m 2^(nb-1), y ~ 1/m (rheo_recip, 8 clocks from 63)
  logic [CoefW-1:0] minv63;
  rheo_delay #(.W(CoefW), .N(63)) u_minv_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(minv_q), .q_o(minv63));
  logic signed [B-1:0] rminv_y71;
  logic [5:0] rminv_nb71;
  logic rminv_nonpos71;
  rheo_recip #(.InW(CoefMantBits), .NonPosNb(1)) u_recip_minv (
    .clk_i(clk_i), .v_i($signed(minv63[CoefMantBits-1:0])), .y_o(rminv_y71), .nb_o(rminv_nb71),
    .nonpos_o(rminv_nonpos71));
  logic [CoefW-CoefMantBits-1:0] minv_sh71;
  rheo_delay #(.W(CoefW - CoefMantBits), .N(8)) u_minv_sh_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(minv63[CoefW-1:CoefMantBits]), .q_o(minv_sh71));
  logic [B-1:0] ltn71;
  logic [EW-1:0] elt71;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_lt (
    .clk_i(clk_i), .v_i(lt68), .mant_o(ltn71), .shift_o(elt71));
  // right shift s = (B-2) + nb - 1 - shift - kMinv - e_lt >= -34 (shift <= 47, e_lt <= 14,
  // nb >= 1), at most 59; a product of at most 2^34 shifted left by 34 still fits t.
  localparam int CapMaxLeft = 36;
  logic signed [PW-1:0] cprod72_q;
  logic [7:0] cs72_q;
  logic nocap72_q, nocap73_q, nocap74_q;
  always_ff @(posedge clk_i) begin
    cprod72_q <= $signed(ltn71) * rminv_y71;
    cs72_q <= 8'(B - 2 - 1 + CoefShiftBias - rheo_consts_pkg::ShiftMinv + CapMaxLeft) +
              8'(rminv_nb71) - 8'(minv_sh71) - 8'(elt71);
    nocap72_q <= rminv_nonpos71;
    nocap73_q <= nocap72_q;
    nocap74_q <= nocap73_q;
  end
  logic signed [W-1:0] cap74;
  logic unused_clip_cap74;  // quiet: beyond the word, mu F_n is the smaller
  rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(8), .MaxLeft(CapMaxLeft)) u_cap (
    .clk_i(clk_i), .v_i(cprod72_q), .sb_i(cs72_q), .out_o(cap74), .clip_o(unused_clip_cap74));

  // ---- stage 75: F_t = min(mu F_n, cap); stages 76-81: F_t^ t ----
  logic signed [W-1:0] mufn74;
  rheo_delay #(.W(W), .N(19)) u_mufn_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(mufn55), .q_o(mufn74));
  logic signed [W-1:0] ft75_q;
  always_ff @(posedge clk_i) ft75_q <= (nocap74_q || mufn74 < cap74) ? mufn74 : cap74;
  logic [B-1:0] ftn78;
  logic [EW-1:0] eft78;
  rheo_normalize #(.N(1), .InW(W), .B(B), .ShiftW(EW)) u_norm_ft (
    .clk_i(clk_i), .v_i(ft75_q), .mant_o(ftn78), .shift_o(eft78));
  logic [3*B-1:0] t78_flat;
  rheo_delay #(.W(3*B), .N(10)) u_t_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({t68[2], t68[1], t68[0]}), .q_o(t78_flat));
  logic signed [PW-1:0] ftprod79_q [3];
  logic [6:0] fts79_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) ftprod79_q[i] <= $signed(ftn78) * $signed(t78_flat[i*B +: B]);
    fts79_q <= 7'(FracU) - 7'(eft78);
  end
  logic signed [W-1:0] ftt81 [3];
  logic clip_ftt81 [3];
  for (genvar i = 0; i < 3; i++) begin : g_ftt
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(7), .MaxLeft(0)) u_ftt (
      .clk_i(clk_i), .v_i(ftprod79_q[i]), .sb_i(fts79_q), .out_o(ftt81[i]), .clip_o(clip_ftt81[i]));
  end

  // ---- stage 82: f = F_n u - F_t t, saturated ----
  logic [3*W-1:0] f81_flat;
  rheo_delay #(.W(3*W), .N(26)) u_f_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i({f55[2], f55[1], f55[0]}), .q_o(f81_flat));
  logic fclip81;
  rheo_delay #(.W(1), .N(26)) u_fclip_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(fclip55[0] | fclip55[1] | fclip55[2]), .q_o(fclip81));
  logic signed [W:0] fo_w [3];
  logic signed [W-1:0] f82_q [3];
  logic fclip82_q;
  always_comb begin
    for (int i = 0; i < 3; i++)
      fo_w[i] = (W+1)'($signed(f81_flat[i*W +: W])) - (W+1)'(ftt81[i]);
  end
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) f82_q[i] <= sat(fo_w[i]);
    fclip82_q <= fclip81 | clip_ftt81[0] | clip_ftt81[1] | clip_ftt81[2] | clip(fo_w[0]) |
                 clip(fo_w[1]) | clip(fo_w[2]);
  end

  // ---- in reach (38) and F_n > 0 (50) wait for f ----
  logic reach82, fn_pos50_q, fn_pos82;
  always_ff @(posedge clk_i) fn_pos50_q <= fn49_q > 0;
  rheo_delay #(.W(1), .N(44)) u_reach_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(reach38_q), .q_o(reach82));
  rheo_delay #(.W(1), .N(32)) u_fnpos_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(fn_pos50_q), .q_o(fn_pos82));

  // ---- stage 83: output registers ----
  logic signed [W-1:0] f83_q [3];
  logic contact83_q, sat83_q;
  logic contact82;
  assign contact82 = reach82 & fn_pos82;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) f83_q[i] <= contact82 ? f82_q[i] : '0;
    contact83_q <= contact82;
    sat83_q <= reach82 & (sat_q[82] | (contact82 & fclip82_q));
  end

  // ---- saturation flags: each clip joins the particle's flag in the stage where it is seen ----
  always_comb begin
    flag_at = '0;
    flag_at[1] = clip1_q;
    flag_at[9] = clip_along9;
    flag_at[15] = clip_proj15[0] | clip_proj15[1] | clip_proj15[2];
    flag_at[16] = clip16_q;
    flag_at[36] = clip_lu36;
    flag_at[37] = clip_ds37_q;
    flag_at[40] = clip_cross40[0] | clip_cross40[1] | clip_cross40[2];
    flag_at[41] = clip_ldot41;
    flag_at[43] = clip_slip43[0] | clip_slip43[1] | clip_slip43[2];
    flag_at[47] = clip_tk47 | clip_tc47 | clip_normal47[0] | clip_normal47[1] | clip_normal47[2];
    flag_at[48] = clip48_q | clip_dpt48_q;
    flag_at[49] = clip49_q;
    flag_at[55] = clip_mufn55;
    flag_at[68] = clip_lt68;
  end
  always_ff @(posedge clk_i) sat_q <= {sat_q[Last-2:0] | flag_at, 1'b0};

  assign valid_o = v_q[Last];
  assign idx_o = idx_out;
  assign f_o = {f83_q[2], f83_q[1], f83_q[0]};
  assign contact_o = v_q[Last] & contact83_q;
  assign sat_o = v_q[Last] & sat83_q;

  logic unused;
  assign unused = unused_clip_cap74 ^ deg_t68;  // a zero dp_t gives l_t = 0 and t = 0 anyway
endmodule
