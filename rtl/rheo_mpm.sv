// Mass-Point Module: one particle per clock (initiation interval 1). From the particle's
// summed edge force f it integrates semi-implicit Euler in folded units and applies the
// constraints:
//   p += minv f + g;  x += p                     (minv = Fu dt^2 / (m Lu), g in P format)
//   fixed: x = x0, p = 0
//   plate particle above the plate: z = plate_z, p.z = min(p.z, plate_z - z_start),
//     plate_f = f.z  (the held particle moves with the plate, as in the reference model)
//   otherwise below the floor: z = 0, p.z = max(p.z, 0)
// Rounding is to nearest, results saturate and raise sat_o. Mirrors rheo::hls::mpm_particle
// bit for bit, for every coefficient word (left shifts included).
//
// Latency: rheo_consts_pkg::MpmLatency = 9 clocks. Every stage holds at most one
// multiplier or one carry chain of <= 34 bits with a few LUT levels around it:
//   0 input register
//   1 partial products of minv f: f[16:0] x mant and f[31:17] x mant (one MULT18X18
//     each, registered inputs and outputs)
//   2 product = sum of the partial products (33-bit carry chain); the shift field's
//     thermometer masks
//   3 coefficient shift by 0/16/32/48, then by 0..15 (three 4:1 mux levels), and the
//     overflow test of the bits that leave the 33-bit window
//   4 rounding (+1 at the half LSB, 34-bit carry chain) and saturation: dp = minv f
//   5 p1 = sat(p + dp); plate_z - z_start
//   6 p  = sat(p1 + g); lim = the clamp bound (plate_z - z_start) << 4, saturated
//   7 x  = sat(x + round(p >> 4)) (one carry chain, the rounding bit as carry-in);
//     fixed particles take x0 and p = 0 here; p.z > lim
//   8 constraints: plate (z > plate_z, 32-bit compare) and floor
// The coefficient shift is done on a 33-bit window of the product: (prod << 28) >> t
// keeps one bit below the result's LSB for the rounding (t = stored shift field,
// s = t - 27 the net right shift of hls::mul_coef with CoefShifts::kMinv), and a sticky
// test that every bit above the window repeats its top bit gives the saturation.
// Multipliers: 6 MULT18X18 (3 products of 32 x 18 bits, two halves each); gravity and dt
// are folded. The globals (g, plate_z, the enables) are read at the stage that uses
// them: the core holds them constant while a pass runs.
module rheo_mpm #(
  parameter int W = 32,      // state word width (rheo_consts_pkg::Width)
  parameter int CoefW = 24,  // packed coefficient {shift, mantissa}
  parameter int IdxW = 12    // particle index carried alongside
) (
  input  logic            clk_i,
  input  logic            rst_ni,
  input  logic            valid_i,
  input  logic [IdxW-1:0] idx_i,
  input  logic [3*W-1:0]  f_i,         // summed internal force, {z, y, x}
  input  logic [3*W-1:0]  x_i,         // position
  input  logic [3*W-1:0]  p_i,         // displacement per step
  input  logic [3*W-1:0]  x0_i,        // home position (fixed particles)
  input  logic [CoefW-1:0] minv_i,     // packed coefficient Fu dt^2 / (m Lu)
  input  logic [1:0]      flags_i,     // {plate, fixed}
  input  logic [3*W-1:0]  g_i,         // gravity displacement per step^2
  input  logic [W-1:0]    plate_z_i,   // plate height (X format)
  input  logic            plate_en_i,
  input  logic            floor_en_i,
  output logic            valid_o,
  output logic [IdxW-1:0] idx_o,
  output logic [3*W-1:0]  x_o,
  output logic [3*W-1:0]  p_o,
  output logic [W-1:0]    plate_f_o,   // f.z when the plate holds the particle, else 0
  output logic            sat_o
);
  localparam int FracX = rheo_consts_pkg::FracX;
  localparam int FracP = rheo_consts_pkg::FracP;
  localparam int MantW = rheo_consts_pkg::CoefMantBits;
  localparam int ShiftW = rheo_consts_pkg::CoefShiftBits;
  localparam int Last = rheo_consts_pkg::MpmLatency - 1;  // index of the output stage
  localparam int XShift = FracP - FracX;  // P -> X right shift of x += p
  // minv f: the low part of f is unsigned (one bit short of a multiplier operand), the
  // high part signed; both fit a MULT18X18 operand.
  localparam int LoW = MantW - 1;
  localparam int HiW = W - LoW;
  localparam int ProdW = W + MantW;  // the full product f * mant
  // Net right shift s = t - Lead of the product (t = stored shift field): hls::mul_coef
  // shifts by shift + kMinv with shift = t - bias. The window works on prod << (Lead + 1):
  // the extra bit keeps the rounding bit, so every t is a right shift.
  localparam int Lead = rheo_consts_pkg::CoefShiftBias - rheo_consts_pkg::ShiftMinv;
  localparam int VecW = ProdW + Lead + 1;
  localparam int YW = W + 1;           // the window: result and its rounding bit
  localparam int CoarseW = YW + 15;    // after the coarse shift, the fine shift is < 16
  localparam int LimW = W + 1 + XShift;  // (plate_z - z_start) << XShift
  // Saturation tests: neighbour steps above the window, at positions CoarseW .. VecW-1
  // (coarse window) and YW .. CoarseW-1 (33-bit window).
  localparam int CoarseMaskW = VecW - CoarseW;
  localparam int FineMaskW = CoarseW - YW;

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_mpm: W must equal rheo_consts_pkg::Width");
  end
  if (HiW > 18 || ShiftW != 6 || Lead < 0) begin : g_split_check
    $error("rheo_mpm: the multiplier split and the two-part shift assume 32-bit words and 6-bit shifts");
  end
  if (Last != 8) begin : g_latency_check
    $error("rheo_mpm: the stages below make MpmLatency = 9");
  end

  // Saturation of a sum one bit wider than a word; the top bit says it clipped.
  function automatic logic [W:0] sat_sum(input logic signed [W:0] s);
    if (s[W] != s[W-1]) sat_sum = {1'b1, s[W], {(W-1){~s[W]}}};
    else sat_sum = {1'b0, s[W-1:0]};
  endfunction

  // A 4:1 multiplexer of coarse-window words, as two levels of 2:1 (LUT logic).
  function automatic logic [CoarseW-1:0] mux4(input logic [1:0] sel,
      input logic [CoarseW-1:0] a0, input logic [CoarseW-1:0] a1,
      input logic [CoarseW-1:0] a2, input logic [CoarseW-1:0] a3);
    mux4 = sel[1] ? (sel[0] ? a3 : a2) : (sel[0] ? a1 : a0);
  endfunction

  // ---- registers, named by the stage that writes them (arrays: one entry per stage) --
  // Carried fields, delayed up to the stage that uses them.
  logic v_q [Last+1];
  logic [IdxW-1:0] idx_q [Last+1];
  logic [1:0] flags_q [Last];              // stages 0..7
  logic signed [W-1:0] fz_q [Last];        // f.z (the plate force), stages 0..7
  logic signed [W-1:0] x_q [7][3];         // old position, stages 0..6
  logic signed [W-1:0] x0_q [7][3];        // home position, stages 0..6
  logic signed [W-1:0] pold_q [5][3];      // old p, stages 0..4
  logic [ShiftW-1:0] t_q [3];              // shift field, stages 0..2
  // stage 0
  logic signed [W-1:0] f_q [3];
  logic signed [MantW-1:0] mant_q;
  // stage 1
  logic signed [MantW+LoW:0] lo_q [3];    // f[LoW-1:0] * mant
  logic signed [MantW+HiW-1:0] hi_q [3];  // f[W-1:LoW] * mant
  // stage 2
  logic signed [ProdW-1:0] prod_q [3];
  logic [CoarseMaskW-1:0] coarse_mask_q;   // bit k: position CoarseW + k is above the window
  logic [FineMaskW-1:0] fine_mask_q;       // bit k: coarse position YW + k is above it
  logic neg_q [2][3];                      // sign of the product, stages 2..3
  // stage 3
  logic signed [YW-1:0] y_q [3];
  logic y_ok_q [3];
  // stages 4..8
  logic signed [W-1:0] dp_q [3];
  logic signed [W-1:0] p1_q [3];
  logic signed [W:0] lim_diff_q;           // stage 5: plate_z - z_start
  logic signed [W-1:0] lim_q [2];          // clamp bound, stages 6..7
  logic lim_clip_q [2];
  logic signed [W-1:0] p_q [3];
  logic signed [W-1:0] xn_q [3];           // stage 7: x (x0 when fixed)
  logic signed [W-1:0] pn_q [3];           // stage 7: p (0 when fixed)
  logic pz_above_lim_q;                    // stage 7: p.z > lim
  logic signed [W-1:0] xo_q [3];
  logic signed [W-1:0] po_q [3];
  logic signed [W-1:0] plate_f_q;
  logic sat_q [5];                         // sticky saturation, stages 4..8

  // ---- combinational parts of the stages ----------------------------------------------
  logic signed [MantW+LoW:0] lo_c [3];
  logic signed [MantW+HiW-1:0] hi_c [3];
  logic signed [ProdW-1:0] prod_c [3];
  logic signed [LimW-1:0] lim_w;
  logic [W:0] lim_c;
  logic [VecW-1:0] vec_c [3];
  logic [CoarseW-1:0] coarse_opt [3][4];
  logic [CoarseW-1:0] fine_opt [3][4], fine_mid [3], fine_last [3][4];
  logic [CoarseW-1:0] coarse [3];
  logic [CoarseMaskW-1:0] coarse_step [3];
  logic [CoarseW-1:0] fine_full [3];
  logic [FineMaskW-1:0] fine_step [3];
  logic signed [YW:0] r_c [3];
  logic [W:0] dp_c [3], p1_c [3], p_c [3], x_c [3];
  logic [W+1:0] x_sum [3];
  logic clip4, clip5, clip6, clip7;
  logic hold, on_floor;

  always_comb begin
    // stage 1: partial products (the low part unsigned: a zero sign bit)
    for (int i = 0; i < 3; i++) begin
      lo_c[i] = $signed({1'b0, f_q[i][LoW-1:0]}) * mant_q;
      hi_c[i] = $signed(f_q[i][W-1:LoW]) * mant_q;
    end
    // stage 2: the product
    for (int i = 0; i < 3; i++) begin
      prod_c[i] = {hi_q[i] + (MantW+HiW)'(lo_q[i] >>> LoW), lo_q[i][LoW-1:0]};
    end
    // stage 3: coarse shift by 16 t[5:4]; the result fits the coarse window only if the
    // bits from CoarseW - 1 + 16 t[5:4] up all equal: a step between neighbours there
    // fails. Then the fine shift by t[3:0] and the same test on the coarse window.
    for (int i = 0; i < 3; i++) begin
      vec_c[i] = VecW'({prod_q[i], {(Lead+1){1'b0}}});
      // Constant shifts and explicit 4:1 multiplexers (a variable shift would map to
      // wide-multiplexer trees with a LUT per leaf).
      for (int c = 0; c < 4; c++) coarse_opt[i][c] = CoarseW'($signed(vec_c[i]) >>> (16 * c));
      coarse[i] = mux4(t_q[2][5:4], coarse_opt[i][0], coarse_opt[i][1], coarse_opt[i][2], coarse_opt[i][3]);
      for (int k = 0; k < CoarseMaskW; k++) begin
        coarse_step[i][k] = vec_c[i][CoarseW+k] ^ vec_c[i][CoarseW+k-1];
      end
      for (int c = 0; c < 4; c++) fine_opt[i][c] = CoarseW'($signed(coarse[i]) >>> (4 * c));
      fine_mid[i] = mux4(t_q[2][3:2], fine_opt[i][0], fine_opt[i][1], fine_opt[i][2], fine_opt[i][3]);
      for (int c = 0; c < 4; c++) fine_last[i][c] = CoarseW'($signed(fine_mid[i]) >>> c);
      fine_full[i] = mux4(t_q[2][1:0], fine_last[i][0], fine_last[i][1], fine_last[i][2], fine_last[i][3]);
      for (int k = 0; k < FineMaskW; k++) begin
        fine_step[i][k] = coarse[i][YW+k] ^ coarse[i][YW+k-1];
      end
    end
    // stage 4: round half up, (y + 1) >> 1, and saturate (to the product's sign)
    clip4 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      r_c[i] = ((YW+1)'(y_q[i]) + 1) >>> 1;
      if (y_ok_q[i] && r_c[i][W] == r_c[i][W-1]) dp_c[i] = {1'b0, r_c[i][W-1:0]};
      else dp_c[i] = {1'b1, neg_q[1][i], {(W-1){~neg_q[1][i]}}};
      clip4 = clip4 | dp_c[i][W];
    end
    // stages 5, 6: p1 = sat(p + dp), p = sat(p1 + g)
    clip5 = 1'b0;
    clip6 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      p1_c[i] = sat_sum((W+1)'(pold_q[4][i]) + (W+1)'(dp_q[i]));
      clip5 = clip5 | p1_c[i][W];
      p_c[i] = sat_sum((W+1)'(p1_q[i]) + (W+1)'($signed(g_i[i*W +: W])));
      clip6 = clip6 | p_c[i][W];
    end
    // stage 6: the clamp bound (plate_z - z_start) << XShift, saturated
    lim_w = LimW'(lim_diff_q) <<< XShift;
    if (lim_w[LimW-1:W-1] != {(LimW-W+1){lim_w[LimW-1]}}) begin
      lim_c = {1'b1, lim_w[LimW-1], {(W-1){~lim_w[LimW-1]}}};
    end else begin
      lim_c = {1'b0, lim_w[W-1:0]};
    end
    // stage 7: x + round(p >> XShift) = x + (p >>> XShift) + p[XShift-1], the rounding
    // bit entering as the carry out of a dummy low bit (one carry chain)
    clip7 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      x_sum[i] = {(W+1)'(x_q[6][i]), 1'b1} + {(W+1)'(p_q[i]) >>> XShift, p_q[i][XShift-1]};
      x_c[i] = sat_sum(x_sum[i][W+1:1]);
      clip7 = clip7 | x_c[i][W];
    end
    // stage 8: plate and floor (fixed particles were settled at stage 7)
    hold = flags_q[7][1] && !flags_q[7][0] && plate_en_i && xn_q[2] > $signed(plate_z_i);
    on_floor = !flags_q[7][0] && !hold && floor_en_i && xn_q[2][W-1];
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      for (int s = 0; s <= Last; s++) v_q[s] <= 1'b0;
    end else begin
      v_q[0] <= valid_i;
      for (int s = 1; s <= Last; s++) v_q[s] <= v_q[s-1];
    end
  end

  always_ff @(posedge clk_i) begin
    // carried fields
    idx_q[0] <= idx_i;
    flags_q[0] <= flags_i;
    fz_q[0] <= f_i[2*W +: W];
    for (int i = 0; i < 3; i++) begin
      x_q[0][i] <= x_i[i*W +: W];
      x0_q[0][i] <= x0_i[i*W +: W];
      pold_q[0][i] <= p_i[i*W +: W];
    end
    t_q[0] <= minv_i[CoefW-1:MantW];
    for (int s = 1; s <= Last; s++) idx_q[s] <= idx_q[s-1];
    for (int s = 1; s < Last; s++) begin
      flags_q[s] <= flags_q[s-1];
      fz_q[s] <= fz_q[s-1];
    end
    for (int s = 1; s < 7; s++) begin
      for (int i = 0; i < 3; i++) begin
        x_q[s][i] <= x_q[s-1][i];
        x0_q[s][i] <= x0_q[s-1][i];
      end
    end
    for (int s = 1; s < 5; s++) begin
      for (int i = 0; i < 3; i++) pold_q[s][i] <= pold_q[s-1][i];
    end
    for (int s = 1; s < 3; s++) t_q[s] <= t_q[s-1];
    // stage 0
    for (int i = 0; i < 3; i++) f_q[i] <= f_i[i*W +: W];
    mant_q <= minv_i[MantW-1:0];
    // stage 1
    for (int i = 0; i < 3; i++) begin
      lo_q[i] <= lo_c[i];
      hi_q[i] <= hi_c[i];
    end
    // stage 2 (the masks are thermometer codes of the shift field)
    for (int i = 0; i < 3; i++) begin
      prod_q[i] <= prod_c[i];
      neg_q[0][i] <= prod_c[i][ProdW-1];
    end
    coarse_mask_q <= {CoarseMaskW{1'b1}} << {t_q[1][5:4], 4'b0};
    fine_mask_q <= {FineMaskW{1'b1}} << t_q[1][3:0];
    for (int i = 0; i < 3; i++) neg_q[1][i] <= neg_q[0][i];
    // stage 3
    for (int i = 0; i < 3; i++) begin
      y_q[i] <= fine_full[i][YW-1:0];
      y_ok_q[i] <= (coarse_step[i] & coarse_mask_q) == '0 && (fine_step[i] & fine_mask_q) == '0;
    end
    // stage 4
    for (int i = 0; i < 3; i++) dp_q[i] <= dp_c[i][W-1:0];
    sat_q[0] <= clip4;
    // stage 5
    for (int i = 0; i < 3; i++) p1_q[i] <= p1_c[i][W-1:0];
    sat_q[1] <= sat_q[0] | clip5;
    lim_diff_q <= (W+1)'($signed(plate_z_i)) - (W+1)'(x_q[4][2]);
    // stage 6
    for (int i = 0; i < 3; i++) p_q[i] <= p_c[i][W-1:0];
    sat_q[2] <= sat_q[1] | clip6;
    lim_q[0] <= lim_c[W-1:0];
    lim_clip_q[0] <= lim_c[W];
    // stage 7
    for (int i = 0; i < 3; i++) begin
      xn_q[i] <= flags_q[6][0] ? x0_q[6][i] : x_c[i][W-1:0];
      pn_q[i] <= flags_q[6][0] ? '0 : p_q[i];
    end
    pz_above_lim_q <= p_q[2] > lim_q[0];
    lim_q[1] <= lim_q[0];
    lim_clip_q[1] <= lim_clip_q[0];
    sat_q[3] <= sat_q[2] | clip7;
    // stage 8
    for (int i = 0; i < 3; i++) begin
      xo_q[i] <= xn_q[i];
      po_q[i] <= pn_q[i];
    end
    plate_f_q <= '0;
    if (hold) begin
      xo_q[2] <= plate_z_i;
      if (pz_above_lim_q) po_q[2] <= lim_q[1];
      plate_f_q <= fz_q[7];
    end else if (on_floor) begin
      xo_q[2] <= '0;
      if (pn_q[2][W-1]) po_q[2] <= '0;
    end
    sat_q[4] <= sat_q[3] | (hold & lim_clip_q[1]);
  end

  assign valid_o = v_q[Last];
  assign idx_o = idx_q[Last];
  assign x_o = {xo_q[2], xo_q[1], xo_q[0]};
  assign p_o = {po_q[2], po_q[1], po_q[0]};
  assign plate_f_o = plate_f_q;
  assign sat_o = v_q[Last] & sat_q[4];
endmodule
