// Block normalisation of wide words (rheo::hls::normalize_wide): N words of InW bits with one
// shared exponent to B-bit operands, value = mant_o * 2^shift_o, shift_o = max(0, n - (B-1))
// with every word in [-2^n, 2^n); rounded to nearest, the one case that rounds up to
// 2^(B-1) held at 2^(B-1) - 1. The same result as rheo_normalize, whose leading-bit
// detection in one stage and one barrel shifter over every shift are too slow and too large
// for the volume unit's words (up to 66 bits, up to 12 words). Here the leading one is found
// per 8-bit group (above the groups whose leading one gives shift 0), and the group that
// holds it also splits the shift: a coarse part, a constant of the group chosen one-hot (an
// AND-OR of a few candidates), and a fine part of 0..7 from the leading one's place in the
// group (an 8-way shift). Latency 4 + OrStage (v_i is stage 0):
//   [1 with OrStage: the OR of the words XOR their signs, registered (many words)]
//   +1 per group: non-empty, its fine shift    +2 the leading group one-hot, u = the coarse
//   shift of 2v    +3 t = floor(u 2^-fine) = floor(v 2^-(shift-1)) (keeps the rounding
//   bit), shift = coarse + fine    +4 mant = (t + 1) >> 1, held
// Ports are packed, word i at [i*InW +: InW] (mantissa i at [i*B +: B]).
// (Loop variables here are named apart from rheo_volume's: Verilator 5.006 reports them as
// hiding each other in a core with two lanes.)
module rheo_volume_norm #(
  parameter int N = 3,
  parameter int InW = 66,
  parameter int B = 35,
  parameter int ShiftW = 6,
  parameter int OrStage = 1
) (
  input  logic              clk_i,
  input  logic [N*InW-1:0]  v_i,
  output logic [N*B-1:0]    mant_o,
  output logic [ShiftW-1:0] shift_o
);
  localparam int G = 8;
  localparam int NG = (InW + G - 1) / G;
  // Groups below G0 hold only leading ones that give shift 0 (n <= B - 1); in group G0 + k
  // a leading one at place p (0..7) gives shift 8 k + p + 1 - M, M = (B - 1) - 8 G0.
  localparam int G0 = (B - 1) / G;
  localparam int M = (B - 1) - G * G0;
  localparam int NK = NG - G0;     // groups looked at: k = 0 .. NK - 1
  // u = floor(2v 2^-coarse): |u| < 2^(B+7) whichever group leads (M >= 1)
  localparam int UW = B + G;
  if (NK < 2 || M < 1 || (1 << ShiftW) <= InW - B) begin : g_param_check
    $error("rheo_volume_norm: words must be wider than the operand, B - 1 must not be a multiple of 8, shifts must fit ShiftW");
  end
  // The coarse shift of group G0 + k: shift less the leading one's place for k >= 1 (8 k +
  // 1 - M > 0); 0 for k = 0, whose shift max(0, p + 1 - M) is all fine.
  function automatic int coarse(input int k);
    coarse = (k == 0) ? 0 : G * k + 1 - M;
  endfunction
  function automatic logic [2:0] fine_of(input int k, input logic [G-1:0] x);
    int len;
    len = 0;
    for (int bt = 0; bt < G; bt++) if (x[bt]) len = bt + 1;
    if (k == 0) fine_of = (len > M) ? 3'(len - M) : 3'd0;
    else fine_of = 3'(len - 1);  // (a group that is empty is not selected)
  endfunction

  // The OR of the words XOR their signs: its bit length is n (NG*G bits, zero above InW).
  logic [InW-1:0] mag_w [N];
  logic [NG*G-1:0] bits_w;
  always_comb begin
    bits_w = '0;
    for (int wd = 0; wd < N; wd++) begin
      mag_w[wd] = v_i[wd*InW +: InW] ^ {InW{v_i[wd*InW+InW-1]}};
      bits_w = bits_w | (NG*G)'(mag_w[wd]);
    end
  end
  logic [NG*G-1:0] bits_s;  // at the group stage's input
  logic [N*InW-1:0] v_s;
  if (OrStage != 0) begin : g_or
    logic [NG*G-1:0] bits_q;
    logic [N*InW-1:0] v_q;
    always_ff @(posedge clk_i) begin
      bits_q <= bits_w;
      v_q <= v_i;
    end
    assign bits_s = bits_q;
    assign v_s = v_q;
  end else begin : g_no_or
    assign bits_s = bits_w;
    assign v_s = v_i;
  end
  if (G0 > 0) begin : g_low
    logic unused_low;
    assign unused_low = ^bits_s[G0*G-1:0];
  end

  // ---- per group: non-empty, and its fine shift ----
  logic [NK-1:0] any_q;
  logic [2:0] fine_q [NK];
  logic [N*InW-1:0] va_q;
  always_ff @(posedge clk_i) begin
    for (int k = 0; k < NK; k++) begin
      any_q[k] <= |bits_s[(G0+k)*G +: G];
      fine_q[k] <= fine_of(k, bits_s[(G0+k)*G +: G]);
    end
    va_q <= v_s;
  end

  // ---- the leading group one-hot (k = 0 also when no group is non-empty: shift 0 or fine
  //      only), its fine shift and coarse constant, u = floor(2v 2^-coarse) ----
  logic [NK-1:0] sel_w;
  logic [2:0] fine_w;
  logic [ShiftW-1:0] base_w;
  logic [UW-1:0] u_w [N];
  always_comb begin
    for (int k = 0; k < NK; k++) begin
      sel_w[k] = any_q[k];
      for (int h = k + 1; h < NK; h++) sel_w[k] = sel_w[k] & ~any_q[h];
    end
    sel_w[0] = ~(|sel_w[NK-1:1]);
    fine_w = '0;
    base_w = '0;
    for (int k = 0; k < NK; k++) begin
      fine_w = fine_w | (sel_w[k] ? fine_q[k] : 3'd0);
      base_w = base_w | (sel_w[k] ? ShiftW'(coarse(k)) : '0);
    end
    for (int wd = 0; wd < N; wd++) begin
      u_w[wd] = '0;
      for (int k = 0; k < NK; k++)
        u_w[wd] = u_w[wd] |
                  (sel_w[k] ? UW'(($signed({va_q[wd*InW +: InW], 1'b0})) >>> coarse(k)) : '0);
    end
  end
  logic [UW-1:0] u_q [N];
  logic [2:0] fine2_q;
  logic [ShiftW-1:0] base2_q, shift3_q;
  always_ff @(posedge clk_i) begin
    for (int wd = 0; wd < N; wd++) u_q[wd] <= u_w[wd];
    fine2_q <= fine_w;
    base2_q <= base_w;
  end

  // ---- t = floor(u 2^-fine) = floor(v 2^-(shift-1)); B+1 bits hold it ----
  logic signed [B:0] t_q [N];
  always_ff @(posedge clk_i) begin
    shift3_q <= base2_q + ShiftW'(fine2_q);
    for (int wd = 0; wd < N; wd++) t_q[wd] <= (B+1)'($signed(u_q[wd]) >>> fine2_q);
  end

  // ---- mant = (t + 1) >> 1 = round(v 2^-shift), held below 2^(B-1) ----
  // r in [-2^(B-1), 2^(B-1)]: the only overflow is r = 2^(B-1) (bits B+1..B-1 = 001)
  logic signed [B+1:0] r_w [N];
  always_comb begin
    for (int wd = 0; wd < N; wd++) r_w[wd] = ((B+2)'(t_q[wd]) + (B+2)'(1)) >>> 1;
  end
  always_ff @(posedge clk_i) begin
    shift_o <= shift3_q;
    for (int wd = 0; wd < N; wd++)
      mant_o[wd*B +: B] <= (r_w[wd][B+1:B-1] == 3'b001) ? {1'b0, {(B-1){1'b1}}} : r_w[wd][B-1:0];
  end
endmodule

// Volume preservation's element unit, one per lane (rheo::hls::volume_element for the
// hardware format): the forces of one tetrahedron (a, b, c, d) from its vertices, its
// six-fold rest volume V6_0 (FracV fraction bits) and its coefficient c:
//   e_k = x_k - x_a (k = b, c, d; exact, W + 1 bits)
//   g_b = e_c x e_d (exact), V6 = e_b . g_b^ (g_b^: VolOperandBits-bit operands, one exponent)
//   D = V6 - V6_0,  P^ = -(D^ c)^
//   e^ (the nine e as 18-bit operands, one exponent), g_b rounded to e^'s scale,
//   g_c = e_d^ x e_b^, g_d = e_b^ x e_c^, g_a = -(g_b + g_c + g_d), g^ (12 operands)
//   f_k = saturate(P^ g_k^ 2^-s),  s = ShiftVolume + c.shift - the exponents of P^, D^, g^
//   and twice e^'s (clamped as in the C++; at -W every non-zero product saturates already)
// Rounding to nearest (half up) at every narrowing, as the C++.
// An element takes two clocks of the lane: its first half (valid_i, !second_i: a = xs_i,
// b = xe_i, V6_0 = {d_i, l_i}) and, always in the very next clock, its second half (c =
// xs_i, d = xe_i, the packed coefficient in l_i); elements may follow back to back, one
// every two clocks. The forces leave in two beats: f_a, f_b (fs_o, fe_o) Latency clocks
// after the first half, f_c, f_d one clock later (Latency after the second half), which
// are the output clocks of the TEM for the element's two slots. A first half without its
// second half gives no output (hls::core_step drops it too).
// A triangle of a 2-D model (its second half's d_i = Y, non-zero) runs as the tetrahedron
// with the virtual vertex d = a + Y y^: e_d = (0, Y, 0) instead of the end particle's
// difference, and g_d = 0 (left out of g_a and of g^'s exponent, so f_d = 0).
// Because an element occupies two clocks, every multiplier is used twice per element:
// in the first clock of a pair it computes one set of partial products, in the second the
// other (the select is the valid bit of the stage before). So the exact 33 x 33 products
// of g_b take 12 MULT18X18 instead of 24, V6's 33 x 35 products 6 instead of 12, g_c and
// g_d's 12 products 6, and the forces' 12 products 6 (one beat each).
// The hardware format's differences e (W + 1 = 33 bits) fit VolOperandBits (35): e's
// normalisation for V6 has exponent 0 and is left out (checked below). A wide operand is
// split into a signed high part and an unsigned 17-bit low part, each one 18-bit operand:
// x y = xh yh 2^34 + (xh yl + xl yh) 2^17 + xl yl, where xh yh 2^34 + xl yl is a
// concatenation (xl yl < 2^34). The cross terms are computed in the first clock, since they
// need one more addition.
// Register index t of each value (t = 0: the second half's input registers; the first
// half's are t = -1, and a, e_b, V6_0 are held from t = 0 on):
//    1 e_b, e_c, e_d (held two clocks)   2-3 g_b's products (cross terms, then high/low)
//    4 cross differences   5 their sum, the high/low difference   6 g_b (exact, 66 bits)
//    7-11 g_b^ (rheo_volume_norm)   12 g_b^, e_b held   13-14 V6's products (products at
//   14, 15)   15 cross sums   16-18 v6_raw   19 v6_raw 2^-(s-1)   20 D = V6 - V6_0 (V6's
//   rounding in the same carry chain)   21-24 D^ (rheo_volume_norm)   25 D^ c   26 -D^ c
//   27-29 P^ (rheo_normalize)   30 / 31 the force products' operands: P^ and g_a^, g_b^
//   (beat 0) / g_c^, g_d^ (beat 1)   31 / 32 products   32-33 / 33-34 forces
//   (rheo_round_shift), then the Latency padding: beat 0 leaves at Latency - 2.
// Beside the V6 path: 2-6 e^ (rheo_volume_norm)   7-8 g_b at e^'s scale   7 e^ held
//    8-10 g_c, g_d's products (operands at 8: the positive terms, 9: the negative ones)
//   11 g_c, g_d   12 g_b + g_c, -g_d   13 g_a   14-18 g^ (rheo_volume_norm), which waits
//   for P^; the force shift is summed on the way (7, 19, 25, 30) and clamped (31).
// Each stage holds one multiplier (registered inputs and output), or one carry chain (at
// most ~70 bits, in the V6 sums), or a leading-bit / barrel-shift step.
// Multipliers: 12 (g_b) + 6 (V6) + 6 (g_c, g_d) + 1 (D^ c) + 6 (forces) = 31 MULT18X18.
module rheo_volume #(
  // clocks from a half's valid_i to that half's valid_o (the core passes its TEM latency:
  // 40, 72 or 92); at least MinLatency = 35, the unit's own pipeline
  parameter int Latency = 40,
  localparam int W = rheo_consts_pkg::Width
) (
  input  logic           clk_i,
  input  logic           rst_ni,
  input  logic           valid_i,   // a half of an element enters
  input  logic           second_i,  // 0: first half (a, b; V6_0), 1: second half (c, d; c)
  input  logic [3*W-1:0] xs_i,      // the slot's start particle position, x at [W-1:0]
  input  logic [3*W-1:0] xe_i,      // the slot's end particle position
  input  logic [W-1:0]   l_i,       // first half: V6_0[31:0]; second: packed coefficient
  input  logic [W-1:0]   d_i,       // first half: V6_0[63:32]; second: a triangle's Y, or 0
  output logic           valid_o,
  output logic [3*W-1:0] fs_o,      // force on the slot's start particle (F words)
  output logic [3*W-1:0] fe_o,      // force on the slot's end particle
  output logic           sat_o      // a force of this beat saturated (StatusVolumeSat)
);
  localparam int B = rheo_consts_pkg::OperandBits;
  localparam int VB = rheo_consts_pkg::VolOperandBits;
  localparam int PW = 2 * B;           // product of two operands
  localparam int MantW = rheo_consts_pkg::CoefMantBits;
  localparam int CoefW = rheo_consts_pkg::CoefW;
  localparam int Bias = rheo_consts_pkg::CoefShiftBias;
  localparam int EW = 6;               // operand exponents
  localparam int XW = W + 1;           // exact differences e
  localparam int LoW = B - 1;          // unsigned low part of a split wide operand
  localparam int HHW = 2 * (XW - LoW); // xh yh of two differences (g_b)
  localparam int LLW = 2 * LoW;        // xl yl
  localparam int GBW = 2 * XW;         // g_b exact: |g_b| < 2^(2W+1)
  localparam int YW = XW + 1;          // a difference of two cross terms of g_b
  localparam int VHW = XW - LoW + VB - LoW;  // eh gh (V6)
  localparam int KW = VHW + LLW;       // eh gh 2^34 + el gl
  localparam int CW = VB + 1;          // eh gl + el gh
  localparam int VRW = XW + VB + 1;    // v6_raw = e_b . g_b^ (three XW x VB products)
  localparam int GvMaxShift = GBW - VB;  // g_b^'s largest exponent
  localparam int GvShW = $clog2(GvMaxShift + 1);
  localparam int EnShW = $clog2(XW - B + 1);  // e^'s exponent (at most XW - B)
  localparam int VS = 3 * rheo_consts_pkg::FracX - rheo_consts_pkg::FracV;  // V6's shift
  localparam int V6W = VRW - (VS - GvMaxShift);  // V6: v6_raw >> at least VS - GvMaxShift
  localparam int DW = ((V6W > 2 * W) ? V6W : 2 * W) + 1;  // D = V6 - V6_0
  localparam int GRW = 2 * B + 1;      // g_b at e^'s scale, g_c, g_d: |g| <= 2^(2B-1)
  localparam int GW = GRW + 1;         // g_a, and every g as normalised
  localparam int SW = 10;              // the force shift while it is summed
  localparam int SbW = 7;              // the force shift, biased by W: 0 .. W + 2B
  localparam int Out0 = 33;            // register index of beat 0's forces
  localparam int MinLatency = Out0 + 2;  // beat 0 leaves at Latency - 2
  localparam int Pad = Latency - MinLatency;
  localparam int OutWords = 6;         // forces per beat: start x, y, z, end x, y, z

  if (Latency < MinLatency) begin : g_latency_check
    $error("rheo_volume: Latency must be at least MinLatency (the unit's own pipeline)");
  end
  // The hardware format's differences pass V6's operands whole (ev.shift = 0 in the C++),
  // wide operands split into an 18-bit signed high part and a 17-bit low part, and V6's
  // shift is a right shift for every exponent of g_b^.
  if (W != 32 || B != 18 || VB != 35 || MantW != B || W + 1 > VB ||
      XW - LoW > B || VB - LoW > B || VS - GvMaxShift < 1 || 2 * W + 2 * B >= (1 << SbW) ||
      GvMaxShift >= 64 || rheo_consts_pkg::FracV > 2 * rheo_consts_pkg::FracX) begin : g_format_check
    $error("rheo_volume: the datapath below is sized for the hardware format (Q5.27, 18- and 35-bit operands)");
  end

  // High part (signed) and low part (LoW bits, unsigned) of a wide operand, each an 18-bit
  // multiplier operand: x = hi 2^LoW + lo.
  function automatic logic signed [B-1:0] hi_e(input logic signed [XW-1:0] x);
    hi_e = B'(x >>> LoW);
  endfunction
  function automatic logic signed [B-1:0] hi_g(input logic signed [VB-1:0] x);
    hi_g = B'(x >>> LoW);
  endfunction
  function automatic logic signed [B-1:0] lo(input logic [LoW-1:0] x);
    lo = {1'b0, x};
  endfunction

  // ---- control: the second half's valid bit by register index (reset), and whether the
  //      input registers hold a first half ----
  logic [Latency-1:0] v_q;  // packed: one shift, no loop
  logic f0_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      v_q <= '0;
      f0_q <= 1'b0;
    end else begin
      v_q <= {v_q[Latency-2:0], valid_i & second_i};
      f0_q <= valid_i & ~second_i;
    end
  end
`ifndef SYNTHESIS
  // The core sends a second half only in the clock right after its first half (it filters
  // malformed pairs before the unit); checked in every model built with --assert.
  always_ff @(posedge clk_i) begin
    if (valid_i && second_i) assert (f0_q);
  end
`endif

  // ---- input registers (t = -1 for a first half, 0 for a second half) ----
  logic signed [W-1:0] xs0_q [3], xe0_q [3];
  logic [W-1:0] l0_q, d0_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) begin
      xs0_q[i] <= xs_i[i*W +: W];
      xe0_q[i] <= xe_i[i*W +: W];
    end
    l0_q <= l_i;
    d0_q <= d_i;
  end

  // ---- t = 0: the first half held (a, e_b = b - a, V6_0) while its second half enters ----
  logic signed [W-1:0] a_q [3];
  logic signed [XW-1:0] eb0_q [3];
  logic [2*W-1:0] v60_q;
  always_ff @(posedge clk_i) begin
    if (f0_q) begin
      for (int i = 0; i < 3; i++) begin
        a_q[i] <= xs0_q[i];
        eb0_q[i] <= XW'(xe0_q[i]) - XW'(xs0_q[i]);
      end
      v60_q <= {d0_q, l0_q};
    end
  end

  // ---- t = 1: e_b, e_c, e_d (exact), held for the two clocks of the element; a
  //      triangle's e_d = (0, Y, 0), Y = d_i zero-extended ----
  // e1_q[0..2] = e_b, [3..5] = e_c, [6..8] = e_d
  logic signed [XW-1:0] e1_q [9];
  logic tri1_q;
  always_ff @(posedge clk_i) begin
    if (v_q[0]) begin
      for (int i = 0; i < 3; i++) begin
        e1_q[i] <= eb0_q[i];
        e1_q[3+i] <= XW'(xs0_q[i]) - XW'(a_q[i]);
        if (|d0_q) e1_q[6+i] <= (i == 1) ? XW'({1'b0, d0_q}) : '0;
        else e1_q[6+i] <= XW'(xe0_q[i]) - XW'(a_q[i]);
      end
      tri1_q <= |d0_q;
    end
  end
  logic tri11;  // at t = 11: the element is a triangle
  rheo_delay #(.W(1), .N(10)) u_tri_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(tri1_q), .q_o(tri11));
  logic [9*XW-1:0] e1_flat;
  always_comb for (int k = 0; k < 9; k++) e1_flat[k*XW +: XW] = e1_q[k];

  // ---- t = 2-6: g_b = e_c x e_d, exact: component i = e_c[j] e_d[k] - e_c[k] e_d[j]
  //      (j, k = i + 1, i + 2 mod 3), each product as four 18 x 18 pieces: P = ec[j] ed[k],
  //      Q = ec[k] ed[j]; multiplier m computes at t = 2 (first clock) the cross pieces
  //      Ph*l, Pl*h, Qh*l, Ql*h, at t = 3 Ph*h, Pl*l, Qh*h, Ql*l ----
  logic [3*GBW-1:0] gb6;  // component i at [i*GBW +: GBW] (t = 6)
  for (genvar i = 0; i < 3; i++) begin : g_gb
    localparam int J = (i + 1) % 3, K = (i + 2) % 3;
    logic signed [B-1:0] l_q [4], r_q [4];
    logic signed [PW-1:0] p_q [4];
    logic signed [YW-1:0] y1_q, y2_q;
    logic signed [YW:0] y_q;
    logic signed [GBW:0] xb_q;
    logic signed [GBW-1:0] gb_q;
    always_ff @(posedge clk_i) begin
      l_q[0] <= hi_e(e1_q[3+J]);
      r_q[0] <= v_q[1] ? lo(e1_q[6+K][LoW-1:0]) : hi_e(e1_q[6+K]);
      l_q[1] <= lo(e1_q[3+J][LoW-1:0]);
      r_q[1] <= v_q[1] ? hi_e(e1_q[6+K]) : lo(e1_q[6+K][LoW-1:0]);
      l_q[2] <= hi_e(e1_q[3+K]);
      r_q[2] <= v_q[1] ? lo(e1_q[6+J][LoW-1:0]) : hi_e(e1_q[6+J]);
      l_q[3] <= lo(e1_q[3+K][LoW-1:0]);
      r_q[3] <= v_q[1] ? hi_e(e1_q[6+J]) : lo(e1_q[6+J][LoW-1:0]);
      for (int m = 0; m < 4; m++) p_q[m] <= l_q[m] * r_q[m];
      // t = 4: the cross pieces (|.| < 2^(XW-1)) as two differences
      y1_q <= YW'(p_q[0]) - YW'(p_q[2]);
      y2_q <= YW'(p_q[1]) - YW'(p_q[3]);
      // t = 5: P - Q of the high and low pieces (concatenations), the cross sum
      xb_q <= (GBW+1)'($signed({p_q[0][HHW-1:0], p_q[1][LLW-1:0]})) -
              (GBW+1)'($signed({p_q[2][HHW-1:0], p_q[3][LLW-1:0]}));
      y_q <= (YW+1)'(y1_q) + (YW+1)'(y2_q);
      // t = 6: g_b (fits GBW bits)
      gb_q <= GBW'(xb_q + ((GBW+1)'(y_q) <<< LoW));
    end
    assign gb6[i*GBW +: GBW] = gb_q;
    logic unused_p;
    assign unused_p = ^{p_q[0][PW-1:HHW], p_q[1][PW-1:LLW], p_q[2][PW-1:HHW], p_q[3][PW-1:LLW]};
  end

  // ---- t = 7-11: g_b^ = g_b as VB-bit operands (rheo::hls normalize_wide<VB>) ----
  logic [3*VB-1:0] gv11;
  logic [EW-1:0] gvs11;
  rheo_volume_norm #(.N(3), .InW(GBW), .B(VB), .ShiftW(EW), .OrStage(1)) u_norm_gv (
    .clk_i(clk_i), .v_i(gb6), .mant_o(gv11), .shift_o(gvs11));

  // ---- t = 12: g_b^ and e_b held for the two clocks of V6's products ----
  logic [3*XW-1:0] eb11;
  rheo_delay #(.W(3*XW), .N(10)) u_eb_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(e1_flat[3*XW-1:0]), .q_o(eb11));
  logic signed [VB-1:0] gv12_q [3];
  logic signed [XW-1:0] eb12_q [3];
  logic [GvShW-1:0] v6a12_q;  // V6's shift less its least value (below)
  always_ff @(posedge clk_i) begin
    if (v_q[11]) begin
      for (int i = 0; i < 3; i++) begin
        gv12_q[i] <= gv11[i*VB +: VB];
        eb12_q[i] <= eb11[i*XW +: XW];
      end
      v6a12_q <= GvShW'(EW'(GvMaxShift) - gvs11);
    end
  end

  // ---- t = 13-18: v6_raw = e_b . g_b^ (exact). Per component two multipliers: the cross
  //      pieces eh gl, el gh (operands at 13, products at 14), then eh gh, el gl (14, 15) ----
  logic signed [CW-1:0] c15 [3];
  logic signed [KW-1:0] k15 [3];  // eh gh 2^34 + el gl
  for (genvar i = 0; i < 3; i++) begin : g_v6
    logic signed [B-1:0] l_q [2], r_q [2];
    logic signed [PW-1:0] p_q [2];
    logic signed [CW-1:0] c_q;
    always_ff @(posedge clk_i) begin
      l_q[0] <= hi_e(eb12_q[i]);
      r_q[0] <= v_q[12] ? lo(gv12_q[i][LoW-1:0]) : hi_g(gv12_q[i]);
      l_q[1] <= lo(eb12_q[i][LoW-1:0]);
      r_q[1] <= v_q[12] ? hi_g(gv12_q[i]) : lo(gv12_q[i][LoW-1:0]);
      for (int m = 0; m < 2; m++) p_q[m] <= l_q[m] * r_q[m];
      c_q <= CW'(p_q[0]) + CW'(p_q[1]);  // t = 15, from the cross pieces
    end
    assign c15[i] = c_q;
    assign k15[i] = $signed({p_q[0][VHW-1:0], p_q[1][LLW-1:0]});  // t = 15
    logic unused_p;
    assign unused_p = ^{p_q[0][PW-1:VHW], p_q[1][PW-1:LLW]};
  end
  logic signed [KW:0] s01_16_q, s2_16_q;
  logic signed [CW:0] c01_16_q, c01_17_q;
  logic signed [KW+1:0] t17_q;
  logic signed [VRW-1:0] v6raw18_q;
  always_ff @(posedge clk_i) begin
    s01_16_q <= (KW+1)'(k15[0]) + (KW+1)'(k15[1]);
    s2_16_q <= (KW+1)'(k15[2]) + ((KW+1)'(c15[2]) <<< LoW);
    c01_16_q <= (CW+1)'(c15[0]) + (CW+1)'(c15[1]);
    t17_q <= (KW+2)'(s01_16_q) + (KW+2)'(s2_16_q);
    c01_17_q <= c01_16_q;
    v6raw18_q <= VRW'(t17_q + ((KW+2)'(c01_17_q) <<< LoW));  // fits VRW bits
  end

  // ---- t = 19: t = floor(v6_raw 2^-(s-1)), s = VS - g_b^'s exponent (the shift_round of
  //      V6: always a right shift, s - 1 >= VS - GvMaxShift - 1, a constant part and a
  //      GvShW-bit amount); t = 20: D = V6 - V6_0 = floor((t + 1) / 2) - V6_0
  //      = (t + 1 - 2 V6_0) >> 1 = (t + {-V6_0, 1}) >> 1: the rounding's +1 and the
  //      subtraction in one carry chain (-V6_0 is formed early, at t = 1) ----
  logic [GvShW-1:0] v6a18;
  rheo_delay #(.W(GvShW), .N(6)) u_v6a_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(v6a12_q), .q_o(v6a18));
  logic signed [2*W:0] nv0_1_q;
  always_ff @(posedge clk_i) nv0_1_q <= -((2*W+1)'($signed(v60_q)));
  logic [2*W:0] nv0_19;
  rheo_delay #(.W(2*W+1), .N(18)) u_nv0_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(nv0_1_q), .q_o(nv0_19));
  logic signed [V6W:0] t19_q;  // |t| <= |v6_raw| 2^-(VS - GvMaxShift - 1) < 2^V6W
  logic signed [DW-1:0] d20_q;
  logic signed [DW:0] dsum_w;
  always_comb dsum_w = (DW+1)'(t19_q) + (DW+1)'($signed({nv0_19, 1'b1}));
  always_ff @(posedge clk_i) begin
    t19_q <= (V6W+1)'((v6raw18_q >>> (VS - GvMaxShift - 1)) >>> v6a18);
    d20_q <= DW'(dsum_w >>> 1);
  end

  // ---- t = 21-24: D^; t = 25: D^ c; t = 26: -D^ c; t = 27-29: P^ ----
  logic signed [B-1:0] dn24;
  logic [EW-1:0] dns24;
  rheo_volume_norm #(.N(1), .InW(DW), .B(B), .ShiftW(EW), .OrStage(0)) u_norm_d (
    .clk_i(clk_i), .v_i(d20_q), .mant_o(dn24), .shift_o(dns24));
  logic [CoefW-1:0] coef24;
  rheo_delay #(.W(CoefW), .N(24)) u_coef_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(l0_q[CoefW-1:0]), .q_o(coef24));
  logic signed [PW-1:0] dc25_q, np26_q;
  always_ff @(posedge clk_i) begin
    dc25_q <= dn24 * $signed(coef24[MantW-1:0]);
    np26_q <= -dc25_q;  // |D^ c| <= 2^(2B-2): no overflow
  end
  logic signed [B-1:0] pn29;
  logic [EW-1:0] pns29;
  rheo_normalize #(.N(1), .InW(PW), .B(B), .ShiftW(EW)) u_norm_p (
    .clk_i(clk_i), .v_i(np26_q), .mant_o(pn29), .shift_o(pns29));

  // ---- beside: t = 2-6: e^ (the nine e as B-bit operands, one exponent) ----
  logic [9*B-1:0] en6;
  logic [EW-1:0] ens6;
  rheo_volume_norm #(.N(9), .InW(XW), .B(B), .ShiftW(EW), .OrStage(1)) u_norm_e (
    .clk_i(clk_i), .v_i(e1_flat), .mant_o(en6), .shift_o(ens6));

  // ---- t = 7-8: g_b at e^'s scale, round(g_b 2^-2s) with s = e^'s exponent: t = floor(g_b
  //      2^-(2s-1)) (an even right shift of 2 g_b by at most 2 EnMaxShift), then (t + 1) >> 1.
  //      Unlike rheo_round_shift it keeps only the GRW + 1 bits of t that reach the result:
  //      |g_b 2^-2s| <= 2^(2B-1) never clips ----
  logic [3*GRW-1:0] gbr8, gbr11;
  for (genvar i = 0; i < 3; i++) begin : g_gbr
    logic signed [GRW:0] t_q;
    logic signed [GRW-1:0] r_q;
    always_ff @(posedge clk_i) begin
      t_q <= (GRW+1)'(($signed({gb6[i*GBW +: GBW], 1'b0})) >>> {ens6[EnShW-1:0], 1'b0});
      r_q <= GRW'(((GRW+2)'(t_q) + (GRW+2)'(1)) >>> 1);
    end
    assign gbr8[i*GRW +: GRW] = r_q;
  end
  rheo_delay #(.W(3*GRW), .N(3)) u_gbr_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(gbr8), .q_o(gbr11));

  // ---- t = 7: e^ held; t = 8-11: g_c = e_d^ x e_b^, g_d = e_b^ x e_c^; per component two
  //      multipliers, the positive term in the first clock (operands 8, products 9), the
  //      negative in the second (9, 10) ----
  logic signed [B-1:0] en7_q [9];  // e_b^ [0..2], e_c^ [3..5], e_d^ [6..8]
  always_ff @(posedge clk_i) begin
    if (v_q[6]) for (int k = 0; k < 9; k++) en7_q[k] <= en6[k*B +: B];
  end
  logic signed [GRW-1:0] gc11 [3], gd11 [3];
  for (genvar i = 0; i < 3; i++) begin : g_gcd
    localparam int J = (i + 1) % 3, K = (i + 2) % 3;
    logic signed [B-1:0] cl_q, cr_q, dl_q, dr_q;
    logic signed [PW-1:0] cp_q, dp_q, cp10_q, dp10_q;
    logic signed [GRW-1:0] gc_q, gd_q;
    always_ff @(posedge clk_i) begin
      cl_q <= v_q[7] ? en7_q[6+J] : en7_q[6+K];  // e_d^[j] e_b^[k] - e_d^[k] e_b^[j]
      cr_q <= v_q[7] ? en7_q[K] : en7_q[J];
      dl_q <= v_q[7] ? en7_q[J] : en7_q[K];      // e_b^[j] e_c^[k] - e_b^[k] e_c^[j]
      dr_q <= v_q[7] ? en7_q[3+K] : en7_q[3+J];
      cp_q <= cl_q * cr_q;
      dp_q <= dl_q * dr_q;
      cp10_q <= cp_q;  // t = 10: the positive terms wait for the negative ones
      dp10_q <= dp_q;
      gc_q <= GRW'(cp10_q) - GRW'(cp_q);  // t = 11
      gd_q <= GRW'(dp10_q) - GRW'(dp_q);
    end
    assign gc11[i] = gc_q;
    assign gd11[i] = gd_q;
  end

  // ---- t = 12-13: g_a = -(g_b + g_c + g_d) = -g_d - (g_b + g_c); a triangle's g_d = 0 ----
  logic signed [GW-1:0] gbc12_q [3], ngd12_q [3], ga13_q [3];
  logic signed [GRW-1:0] gb12_q [3], gc12_q [3], gd12_q [3], gb13_q [3], gc13_q [3], gd13_q [3];
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++) begin
      gbc12_q[i] <= GW'($signed(gbr11[i*GRW +: GRW])) + GW'(gc11[i]);
      ngd12_q[i] <= tri11 ? '0 : -(GW'(gd11[i]));
      gb12_q[i] <= gbr11[i*GRW +: GRW];
      gc12_q[i] <= gc11[i];
      gd12_q[i] <= tri11 ? '0 : gd11[i];
      ga13_q[i] <= ngd12_q[i] - gbc12_q[i];  // |g_a| <= 3 2^(2B-1) < 2^(GW-1)
      gb13_q[i] <= gb12_q[i];
      gc13_q[i] <= gc12_q[i];
      gd13_q[i] <= gd12_q[i];
    end
  end

  // ---- t = 14-18: g^, the twelve g (g_a, g_b, g_c, g_d) as B-bit operands ----
  logic [12*GW-1:0] g13;
  always_comb begin
    for (int i = 0; i < 3; i++) begin
      g13[i*GW +: GW] = ga13_q[i];
      g13[(3+i)*GW +: GW] = GW'(gb13_q[i]);
      g13[(6+i)*GW +: GW] = GW'(gc13_q[i]);
      g13[(9+i)*GW +: GW] = GW'(gd13_q[i]);
    end
  end
  logic [12*B-1:0] gn18;
  logic [EW-1:0] gns18;
  rheo_volume_norm #(.N(12), .InW(GW), .B(B), .ShiftW(EW), .OrStage(1)) u_norm_g (
    .clk_i(clk_i), .v_i(g13), .mant_o(gn18), .shift_o(gns18));
  // g_a^, g_b^ wait for beat 0 (t = 29), g_c^, g_d^ for beat 1 (t = 30)
  logic [6*B-1:0] gab29, gcd30;
  rheo_delay #(.W(6*B), .N(11)) u_gab_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(gn18[6*B-1:0]), .q_o(gab29));
  rheo_delay #(.W(6*B), .N(12)) u_gcd_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(gn18[12*B-1:6*B]), .q_o(gcd30));

  // ---- the force shift s = ShiftVolume + c.shift - 2 e^'s - g^'s - D^'s - P^'s exponent,
  //      summed as the exponents come (7, 19, 25, 30), clamped to [-W, 2B] at 31 (below -W
  //      every non-zero product saturates, as at the C++'s -64; beyond 2B every product
  //      rounds to 0) and biased by W ----
  logic [CoefW-MantW-1:0] cst6;
  rheo_delay #(.W(CoefW - MantW), .N(6)) u_cst_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(l0_q[CoefW-1:MantW]), .q_o(cst6));
  logic signed [SW-1:0] s7_q, s18, s19_q, s24, s25_q, s29, s30_q;
  logic [SbW-1:0] sb31_q;
  always_ff @(posedge clk_i) begin
    s7_q <= SW'(rheo_consts_pkg::ShiftVolume - Bias) + SW'(cst6) - SW'(ens6) - SW'(ens6);
    s19_q <= s18 - SW'(gns18);
    s25_q <= s24 - SW'(dns24);
    s30_q <= s29 - SW'(pns29);
    if (v_q[30]) begin  // held for both beats
      if (s30_q < SW'(-W)) sb31_q <= '0;
      else if (s30_q > SW'(2 * B)) sb31_q <= SbW'(W + 2 * B);
      else sb31_q <= SbW'(s30_q + SW'(W));
    end
  end
  rheo_delay #(.W(SW), .N(11)) u_s7_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(s7_q), .q_o(s18));
  rheo_delay #(.W(SW), .N(5)) u_s19_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(s19_q), .q_o(s24));
  rheo_delay #(.W(SW), .N(4)) u_s25_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(s25_q), .q_o(s29));

  // ---- t = 30-34: the forces P^ g_k^ 2^-s, saturated: beat 0 (f_a, f_b) has its operands
  //      at 30 and its forces at 33, beat 1 (f_c, f_d) one clock later ----
  logic signed [B-1:0] pn30_q, fp_q;
  logic signed [B-1:0] fg_q [OutWords];
  logic signed [PW-1:0] fprod_q [OutWords];
  always_ff @(posedge clk_i) begin
    pn30_q <= pn29;
    fp_q <= v_q[29] ? pn29 : pn30_q;
    for (int o = 0; o < OutWords; o++) begin
      fg_q[o] <= v_q[29] ? gab29[o*B +: B] : gcd30[o*B +: B];
      fprod_q[o] <= fp_q * fg_q[o];
    end
  end
  logic [OutWords*W-1:0] f33;  // fs at [3*W-1:0], fe above (t = 33, 34)
  logic [OutWords-1:0] clip33;
  for (genvar o = 0; o < OutWords; o++) begin : g_f
    rheo_round_shift #(.InW(PW), .OutW(W), .ShiftW(SbW), .MaxLeft(W)) u_f (
      .clk_i(clk_i), .v_i(fprod_q[o]), .sb_i(sb31_q), .out_o(f33[o*W +: W]),
      .clip_o(clip33[o]));
  end

  // ---- the Latency padding, then the outputs ----
  logic [OutWords*W:0] out_w, out_q;
  assign out_w = {|clip33, f33};
  rheo_delay #(.W(OutWords*W + 1), .N(Pad)) u_pad_d (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(out_w), .q_o(out_q));
  assign valid_o = v_q[Latency-2] | v_q[Latency-1];
  assign fs_o = out_q[3*W-1:0];
  assign fe_o = out_q[OutWords*W-1:3*W];
  assign sat_o = valid_o & out_q[OutWords*W];

  logic unused;
  assign unused = ^{l0_q[W-1:CoefW], coef24[CoefW-1:MantW], ens6[EW-1:EnShW]};
endmodule
