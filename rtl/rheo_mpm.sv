// Mass-Point Module: one particle per clock (initiation interval 1). From the particle's
// summed edge force f it integrates semi-implicit Euler in folded units and applies the
// constraints:
//   p += minv f + g;  x += p                     (minv = Fu dt^2 / (m Lu), g in P format)
//   fixed: x = x0, p = 0
//   plate particle above the plate (z > plate_z), or on the plate in the previous step
//     (z_start = plate_prev_i, prev_valid_i) and moving faster than it (p.z > lim, lim =
//     (plate_z - z_start) << 4): z = plate_z, p.z = min(p.z, lim),
//     plate_f = f.z  (the held particle moves with the plate, as in the reference model)
//   with hold_en_i, a plate particle held in the previous step (z_start = plate_prev_i)
//     that pushes (f.z > 0): z = plate_z, p.z = plate_z - z_start, plate_f = f.z
//   otherwise below the floor: z = 0, p.z = max(p.z, 0)
// Rounding is to nearest, results saturate and raise sat_o. Mirrors rheo::hls::mpm_particle
// bit for bit, for every coefficient word (left shifts included).
//
// Latency: rheo_consts_pkg::MpmLatency = 8 clocks. Every stage holds at most one
// multiplier or one carry chain of <= 34 bits with a few LUT levels around it:
//   0 input register
//   1 partial products of minv f: f[16:0] x mant and f[31:17] x mant (one MULT18X18
//     each, registered inputs and outputs)
//   2 product = sum of the partial products (33-bit carry chain), then the coefficient
//     shift by 0/16/32/48 (a 4:1 multiplexer) into a 49-bit window
//   3 shift by 0..15 (two 4:1 multiplexer levels) into a 34-bit window y (the result,
//     its rounding bit and one bit for the rounding's carry) and the saturation test
//   4 p1 = sat(p + dp): dp = (y >> 1) + y[0] (round half up, the rounding bit as carry-in
//     of the p + dp carry chain) or the saturated word; plate_z - z_start
//   5 p  = sat(p1 + g); lim = the clamp bound (plate_z - z_start) << 4, saturated
//   6 x  = sat(x + round(p >> 4)) (one carry chain, the rounding bit as carry-in);
//     fixed particles take x0 and p = 0 here; p.z > lim
//   7 constraints: plate (z > plate_z, or on it before and p.z > lim) and floor
// The coefficient shift works on prod << 28 shifted right by t (t = stored shift field;
// s = t - 27 is the net right shift of hls::mul_coef with CoefShifts::kMinv), so every
// shift is a right shift that keeps one bit below the result's LSB for the rounding.
// dp = (y + 1) >> 1 fits a word for y in [-2^32 - 1, 2^32 - 2]: it saturates when a bit
// above the window differs from the window's top bit (tested on the bits each shift step
// drops) or when y is outside that range within the window.
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
  input  logic            hold_en_i,   // hold while pushing (previous plate height valid)
  input  logic            prev_valid_i,  // plate_prev_i holds the previous step's height
  input  logic [W-1:0]    plate_prev_i,  // plate height of the previous step
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
  localparam int YW = W + 2;           // the window: result, rounding bit, carry room
  localparam int CoarseW = YW + 15;    // after the coarse shift, the fine shift is < 16
  localparam int LimW = W + 1 + XShift;  // (plate_z - z_start) << XShift
  // Saturation tests: neighbour steps above the window, at positions CoarseW .. VecW-1
  // of the product vector (coarse window) and YW .. CoarseW-1 of the coarse window.
  localparam int CoarseMaskW = VecW - CoarseW;
  localparam int FineMaskW = CoarseW - YW;
  localparam int Groups = (CoarseMaskW + 3) / 4;  // coarse steps ORed in fours at stage 2

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_mpm: W must equal rheo_consts_pkg::Width");
  end
  if (HiW > 18 || ShiftW != 6 || Lead < 0) begin : g_split_check
    $error("rheo_mpm: the multiplier split and the two-part shift assume 32-bit words and 6-bit shifts");
  end
  if (Last != 7) begin : g_latency_check
    $error("rheo_mpm: the stages below make MpmLatency = 8");
  end

  // Saturation of a sum one bit wider than a word; the top bit says it clipped.
  function automatic logic [W:0] sat_sum(input logic signed [W:0] s);
    if (s[W] != s[W-1]) sat_sum = {1'b1, s[W], {(W-1){~s[W]}}};
    else sat_sum = {1'b0, s[W-1:0]};
  endfunction

  // A 4:1 multiplexer of coarse-window words, as two levels of 2:1 (LUT logic; a
  // variable shift would map to wide-multiplexer trees with a LUT per leaf).
  function automatic logic [CoarseW-1:0] mux4(input logic [1:0] sel,
      input logic [CoarseW-1:0] a0, input logic [CoarseW-1:0] a1,
      input logic [CoarseW-1:0] a2, input logic [CoarseW-1:0] a3);
    mux4 = sel[1] ? (sel[0] ? a3 : a2) : (sel[0] ? a1 : a0);
  endfunction

  // ---- registers, named by the stage that writes them (arrays: one entry per stage) --
  // Carried fields, delayed up to the stage that uses them.
  logic v_q [Last+1];
  logic [IdxW-1:0] idx_q [Last+1];
  logic [1:0] flags_q [Last];              // stages 0..6
  logic signed [W-1:0] fz_q [Last];        // f.z (the plate force), stages 0..6
  logic fz_pos_q;                          // stage 6: f.z > 0
  logic signed [W-1:0] x_q [6][3];         // old position, stages 0..5
  logic signed [W-1:0] x0_q [6][3];        // home position, stages 0..5
  logic signed [W-1:0] pold_q [4][3];      // old p, stages 0..3
  logic [ShiftW-1:0] t_q [3];              // shift field, stages 0..2
  // stage 0
  logic signed [W-1:0] f_q [3];
  logic signed [MantW-1:0] mant_q;
  // stage 1
  logic signed [MantW+LoW:0] lo_q [3];    // f[LoW-1:0] * mant
  logic signed [MantW+HiW-1:0] hi_q [3];  // f[W-1:LoW] * mant
  logic [CoarseMaskW-1:0] coarse_mask_q;   // bit k: position CoarseW + k is above the window
  // stage 2
  logic [CoarseW-1:0] coarse_q [3];
  logic [Groups-1:0] coarse_steps_q [3];   // a step above the coarse window, by fours
  logic neg_q [2][3];                      // sign of the product, stages 2..3
  logic [FineMaskW-1:0] fine_mask_q;       // bit k: coarse position YW + k is above y
  logic [CoarseW-1:0] ones_mask_q;         // coarse positions of y[W-1:0]
  // stage 3
  logic signed [W:0] half_q [3];           // y >> 1
  logic round_q [3];                       // y[0]
  logic dp_ok_q [3];                       // dp = half + round fits a word
  // stages 4..7
  logic signed [W-1:0] p1_q [3];
  logic signed [W:0] lim_diff_q;           // stage 4: plate_z - z_start
  logic signed [W-1:0] p_q [3];
  logic signed [W-1:0] lim_q [2];          // clamp bound, stages 5..6
  logic lim_clip_q [2];
  logic signed [W-1:0] xn_q [3];           // stage 6: x (x0 when fixed)
  logic signed [W-1:0] pn_q [3];           // stage 6: p (0 when fixed)
  logic pz_above_lim_q;                    // stage 6: p.z > lim
  logic was_held_q;                        // stage 6: z_start = previous plate height
  logic signed [W-1:0] xo_q [3];
  logic signed [W-1:0] po_q [3];
  logic signed [W-1:0] plate_f_q;
  logic [2:0] clip_q [3];                  // saturation per component, stages 4..6
  logic sat_q [3];                         // sticky saturation of stages < s, s = 5..7

  // ---- combinational parts of the stages ----------------------------------------------
  logic signed [MantW+LoW:0] lo_c [3];
  logic signed [MantW+HiW-1:0] hi_c [3];
  logic signed [ProdW-1:0] prod_c [3];
  logic [VecW-1:0] vec_c [3];
  logic [CoarseW-1:0] coarse_opt [3][4];
  logic [4*Groups-1:0] coarse_step [3];
  logic [CoarseW-1:0] fine_opt [3][4], fine_mid [3], fine_last [3][4], fine_c [3];
  logic [FineMaskW-1:0] fine_step [3];
  logic [YW-1:0] y_c [3];
  logic y_low_ones [3];
  logic dp_ok_c [3];
  logic signed [W:0] dp_word [3];
  logic dp_carry [3];
  logic [W+1:0] p1_sum [3];
  logic signed [LimW-1:0] lim_w;
  logic [W:0] lim_c;
  logic [W:0] p1_c [3], p_c [3], x_c [3];
  logic [W+1:0] x_sum [3];
  logic [2:0] clip4, clip5, clip6;
  logic hold, stick, on_floor;

  always_comb begin
    // stage 1: partial products (the low part unsigned: a zero sign bit)
    for (int i = 0; i < 3; i++) begin
      lo_c[i] = $signed({1'b0, f_q[i][LoW-1:0]}) * mant_q;
      hi_c[i] = $signed(f_q[i][W-1:LoW]) * mant_q;
    end
    // stage 2: the product, then the shift by 16 t[5:4]. The result fits the coarse
    // window only if the bits from CoarseW - 1 + 16 t[5:4] up all equal: a step between
    // neighbours there fails (steps ORed in fours here, the rest at stage 3).
    for (int i = 0; i < 3; i++) begin
      prod_c[i] = {hi_q[i] + (MantW+HiW)'(lo_q[i] >>> LoW), lo_q[i][LoW-1:0]};
      vec_c[i] = VecW'({prod_c[i], {(Lead+1){1'b0}}});
      for (int c = 0; c < 4; c++) coarse_opt[i][c] = CoarseW'($signed(vec_c[i]) >>> (16 * c));
      coarse_step[i] = '0;
      for (int k = 0; k < CoarseMaskW; k++) begin
        coarse_step[i][k] = (vec_c[i][CoarseW+k] ^ vec_c[i][CoarseW+k-1]) & coarse_mask_q[k];
      end
    end
    // stage 3: the shift by t[3:0], its saturation test on the coarse window, and the
    // range test: y[33:32] = 00 or 11 fits except y = 2^32 - 1 (rounds out of the word),
    // 10 fits only as y = -2^32 - 1 (rounds to -2^31), 01 never. y[31:0] all ones is
    // tested on the coarse window with a mask, beside the multiplexers, not after them.
    for (int i = 0; i < 3; i++) begin
      for (int c = 0; c < 4; c++) fine_opt[i][c] = CoarseW'($signed(coarse_q[i]) >>> (4 * c));
      fine_mid[i] = mux4(t_q[2][3:2], fine_opt[i][0], fine_opt[i][1], fine_opt[i][2], fine_opt[i][3]);
      for (int c = 0; c < 4; c++) fine_last[i][c] = CoarseW'($signed(fine_mid[i]) >>> c);
      fine_c[i] = mux4(t_q[2][1:0], fine_last[i][0], fine_last[i][1], fine_last[i][2], fine_last[i][3]);
      y_c[i] = fine_c[i][YW-1:0];
      for (int k = 0; k < FineMaskW; k++) begin
        fine_step[i][k] = coarse_q[i][YW+k] ^ coarse_q[i][YW+k-1];
      end
      y_low_ones[i] = (coarse_q[i] & ones_mask_q) == ones_mask_q;
      dp_ok_c[i] = coarse_steps_q[i] == '0 && (fine_step[i] & fine_mask_q) == '0 &&
                   (y_c[i][W+1] == y_c[i][W] ? !(!y_c[i][W] && y_low_ones[i])
                                              : y_c[i][W+1] && y_low_ones[i]);
    end
    // stage 4: p1 = sat(p + dp), dp = (y >> 1) + y[0] or the saturated word; the
    // rounding bit enters as the carry out of a dummy low bit (one carry chain)
    for (int i = 0; i < 3; i++) begin
      dp_word[i] = dp_ok_q[i] ? half_q[i] : {{2{neg_q[1][i]}}, {(W-1){~neg_q[1][i]}}};
      dp_carry[i] = dp_ok_q[i] & round_q[i];
      p1_sum[i] = {(W+1)'(pold_q[3][i]), 1'b1} + {dp_word[i], dp_carry[i]};
      p1_c[i] = sat_sum(p1_sum[i][W+1:1]);
      clip4[i] = !dp_ok_q[i] | p1_c[i][W];
      // stage 5: p = sat(p1 + g)
      p_c[i] = sat_sum((W+1)'(p1_q[i]) + (W+1)'($signed(g_i[i*W +: W])));
      clip5[i] = p_c[i][W];
    end
    // stage 5: the clamp bound (plate_z - z_start) << XShift, saturated
    lim_w = LimW'(lim_diff_q) <<< XShift;
    if (lim_w[LimW-1:W-1] != {(LimW-W+1){lim_w[LimW-1]}}) begin
      lim_c = {1'b1, lim_w[LimW-1], {(W-1){~lim_w[LimW-1]}}};
    end else begin
      lim_c = {1'b0, lim_w[W-1:0]};
    end
    // stage 6: x + round(p >> XShift) = x + (p >>> XShift) + p[XShift-1], the rounding
    // bit as the carry of a dummy low bit
    for (int i = 0; i < 3; i++) begin
      x_sum[i] = {(W+1)'(x_q[5][i]), 1'b1} + {(W+1)'(p_q[i]) >>> XShift, p_q[i][XShift-1]};
      x_c[i] = sat_sum(x_sum[i][W+1:1]);
      clip6[i] = x_c[i][W];
    end
    // stage 7: plate and floor (fixed particles were settled at stage 6)
    // A particle on the plate in the previous step stays while it moves faster than the
    // plate (p.z > lim, decided on the P word as the reference decides v > V_plate).
    hold = flags_q[6][1] && !flags_q[6][0] && plate_en_i &&
           (xn_q[2] > $signed(plate_z_i) || (prev_valid_i && was_held_q && pz_above_lim_q));
    stick = flags_q[6][1] && !flags_q[6][0] && plate_en_i && !hold && hold_en_i &&
            was_held_q && fz_pos_q;
    on_floor = !flags_q[6][0] && !hold && !stick && floor_en_i && xn_q[2][W-1];
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
    // f.z > 0 for stage 7, compared a stage ahead (f.z only travels): stage 7 then holds
    // one 32-bit compare (the plate's) before its selects, not two.
    fz_pos_q <= fz_q[5] > 0;
    for (int s = 1; s < 6; s++) begin
      for (int i = 0; i < 3; i++) begin
        x_q[s][i] <= x_q[s-1][i];
        x0_q[s][i] <= x0_q[s-1][i];
      end
    end
    for (int s = 1; s < 4; s++) begin
      for (int i = 0; i < 3; i++) pold_q[s][i] <= pold_q[s-1][i];
    end
    for (int s = 1; s < 3; s++) t_q[s] <= t_q[s-1];
    // stage 0
    for (int i = 0; i < 3; i++) f_q[i] <= f_i[i*W +: W];
    mant_q <= minv_i[MantW-1:0];
    // stage 1 (the masks are thermometer codes of the shift field)
    for (int i = 0; i < 3; i++) begin
      lo_q[i] <= lo_c[i];
      hi_q[i] <= hi_c[i];
    end
    coarse_mask_q <= {CoarseMaskW{1'b1}} << {t_q[0][5:4], 4'b0};
    // stage 2
    for (int i = 0; i < 3; i++) begin
      coarse_q[i] <= mux4(t_q[1][5:4], coarse_opt[i][0], coarse_opt[i][1], coarse_opt[i][2],
                          coarse_opt[i][3]);
      for (int g = 0; g < Groups; g++) coarse_steps_q[i][g] <= |coarse_step[i][4*g +: 4];
      neg_q[0][i] <= prod_c[i][ProdW-1];
      neg_q[1][i] <= neg_q[0][i];
    end
    fine_mask_q <= {FineMaskW{1'b1}} << t_q[1][3:0];
    ones_mask_q <= CoarseW'({W{1'b1}}) << t_q[1][3:0];
    // stage 3
    for (int i = 0; i < 3; i++) begin
      half_q[i] <= y_c[i][YW-1:1];
      round_q[i] <= y_c[i][0];
      dp_ok_q[i] <= dp_ok_c[i];
    end
    // stage 4
    for (int i = 0; i < 3; i++) p1_q[i] <= p1_c[i][W-1:0];
    clip_q[0] <= clip4;
    lim_diff_q <= (W+1)'($signed(plate_z_i)) - (W+1)'(x_q[3][2]);
    // stage 5
    for (int i = 0; i < 3; i++) p_q[i] <= p_c[i][W-1:0];
    clip_q[1] <= clip5;
    sat_q[0] <= |clip_q[0];
    lim_q[0] <= lim_c[W-1:0];
    lim_clip_q[0] <= lim_c[W];
    // stage 6
    for (int i = 0; i < 3; i++) begin
      xn_q[i] <= flags_q[5][0] ? x0_q[5][i] : x_c[i][W-1:0];
      pn_q[i] <= flags_q[5][0] ? '0 : p_q[i];
    end
    pz_above_lim_q <= p_q[2] > lim_q[0];
    was_held_q <= x_q[5][2] == plate_prev_i;
    lim_q[1] <= lim_q[0];
    lim_clip_q[1] <= lim_clip_q[0];
    clip_q[2] <= clip6;
    sat_q[1] <= sat_q[0] | (|clip_q[1]);
    // stage 7
    for (int i = 0; i < 3; i++) begin
      xo_q[i] <= xn_q[i];
      po_q[i] <= pn_q[i];
    end
    plate_f_q <= '0;
    if (hold) begin
      xo_q[2] <= plate_z_i;
      if (pz_above_lim_q) po_q[2] <= lim_q[1];
      plate_f_q <= fz_q[6];
    end else if (stick) begin
      xo_q[2] <= plate_z_i;
      po_q[2] <= lim_q[1];
      plate_f_q <= fz_q[6];
    end else if (on_floor) begin
      xo_q[2] <= '0;
      if (pn_q[2][W-1]) po_q[2] <= '0;
    end
    sat_q[2] <= sat_q[1] | (|clip_q[2]) | ((hold | stick) & lim_clip_q[1]);
  end

  assign valid_o = v_q[Last];
  assign idx_o = idx_q[Last];
  assign x_o = {xo_q[2], xo_q[1], xo_q[0]};
  assign p_o = {po_q[2], po_q[1], po_q[0]};
  assign plate_f_o = plate_f_q;
  assign sat_o = v_q[Last] & sat_q[2];
endmodule
