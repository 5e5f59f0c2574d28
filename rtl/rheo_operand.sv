// Building blocks of the TEM's narrow-operand datapath (rheo::hls::normalize,
// rheo::hls::shift_round + saturate of hls/rheo_kernel.hpp). Each is pipelined so that a
// stage holds one short carry chain or a few LUT levels.

// Block normalisation: N words of InW bits with one shared exponent to B-bit operands,
// value = mant_o * 2^shift_o. shift_o = max(0, n - (B-1)) with every word in [-2^n, 2^n);
// the mantissas are rounded to nearest, and the one case that rounds up to 2^(B-1) is held
// at 2^(B-1) - 1.
// Latency 3: leading-bit detection, shift, rounding. Ports are packed, word i at
// [i*InW +: InW] (mantissa i at [i*B +: B]).
module rheo_normalize #(
  parameter int N = 3,
  parameter int InW = 32,
  parameter int B = 18,
  parameter int ShiftW = 6
) (
  input  logic                 clk_i,
  input  logic [N*InW-1:0]     v_i,
  output logic [N*B-1:0]       mant_o,
  output logic [ShiftW-1:0]    shift_o
);
  logic signed [InW-1:0] v [N];
  always_comb begin
    for (int i = 0; i < N; i++) v[i] = v_i[i*InW +: InW];
  end
  // ---- stage 1: n = leading-bit count of the OR of the words XOR their signs ----
  // The leading one is found in parallel (bit b is it iff no higher bit is set), and the
  // shift is an OR of the candidates' constants: AND/OR logic that maps to a balanced LUT
  // tree, not to a priority chain of multiplexers.
  logic [InW-1:0] bits, higher;  // higher[b]: a bit above b is set
  logic [ShiftW-1:0] shift_w;
  always_comb begin
    bits = '0;
    for (int i = 0; i < N; i++) bits = bits | (v[i] ^ {InW{v[i][InW-1]}});
    higher[InW-1] = 1'b0;
    for (int b = InW - 2; b >= 0; b--) higher[b] = higher[b+1] | bits[b+1];
    shift_w = '0;
    for (int b = B - 1; b < InW; b++) begin
      shift_w = shift_w | ((bits[b] & ~higher[b]) ? ShiftW'(b - (B - 1) + 1) : '0);
    end
  end
  logic signed [InW-1:0] v1_q [N];
  logic [ShiftW-1:0] shift1_q, shift2_q;
  // ---- stage 2: t = floor(v 2^-(shift-1)): keeps the rounding bit; B+1 bits hold it ----
  logic signed [B:0] t_q [N];
  always_ff @(posedge clk_i) begin
    shift1_q <= shift_w;
    shift2_q <= shift1_q;
    shift_o <= shift2_q;
    for (int i = 0; i < N; i++) begin
      v1_q[i] <= v[i];
      t_q[i] <= (B+1)'(($signed({v1_q[i], 1'b0})) >>> shift1_q);
    end
  end
  // ---- stage 3: mant = (t + 1) >> 1 = round(v 2^-shift), held below 2^(B-1) ----
  // r in [-2^(B-1), 2^(B-1)]: the only overflow is r = 2^(B-1) (bits B+1..B-1 = 001)
  logic signed [B+1:0] r_w [N];
  always_comb begin
    for (int i = 0; i < N; i++) r_w[i] = ((B+2)'(t_q[i]) + (B+2)'(1)) >>> 1;
  end
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < N; i++)
      mant_o[i*B +: B] <= (r_w[i][B+1:B-1] == 3'b001) ? {1'b0, {(B-1){1'b1}}} : r_w[i][B-1:0];
  end
endmodule

// out = saturate_OutW(round_to_nearest(v 2^-s)) for s >= -MaxLeft (s <= 0: exact left
// shift), clip_o = it saturated. The caller gives sb_i = s + MaxLeft >= 0, so one right
// shifter serves both directions: t = (v 2^(1+MaxLeft)) >> sb = floor(v 2^-(s-1)) keeps the
// rounding bit. Latency 2: that barrel shift, then the rounding (t + 1) >> 1 and the range
// check. The carry chain of the +1 spans only the OutW + 1 bits that reach the output; the
// bits above are checked for all-zeros / all-ones in parallel with it, and its carry-out
// decides which of the two the result needs.
module rheo_round_shift #(
  parameter int InW = 36,
  parameter int OutW = 32,
  parameter int ShiftW = 7,  // unsigned biased shift amount
  parameter int MaxLeft = 0
) (
  input  logic                     clk_i,
  input  logic signed [InW-1:0]    v_i,
  input  logic [ShiftW-1:0]        sb_i,   // s + MaxLeft
  output logic signed [OutW-1:0]   out_o,
  output logic                     clip_o
);
  localparam int TW = InW + 1 + MaxLeft;
  localparam int LoW = OutW + 1;  // bits of t that reach the output: u[OutW:1], u = t + 1
  if (TW <= LoW) begin : g_width_check
    $error("rheo_round_shift: the shifted value must be wider than OutW + 1");
  end
  logic signed [TW-1:0] t_q;
  always_ff @(posedge clk_i) t_q <= (TW'(v_i) <<< (1 + MaxLeft)) >>> sb_i;
  // u = t + 1 (no overflow: |t| < 2^(TW-1) - 1). u's low bits with the carry out of them:
  logic [LoW:0] lo_sum;
  // keep: ABC sees carry-chain outputs as arriving with the flip-flops and would fold
  // hi_ones / hi_zeros into a LUT tree below the late carry-out (five LUT levels after the
  // chain in the TEM); as kept nets they are computed beside the chain and the carry-out
  // meets one LUT for fits and one for the output mux.
  (* keep *) logic hi_ones, hi_zeros;
  (* keep *) logic fits;
  always_comb begin
    lo_sum = {1'b0, t_q[LoW-1:0]} + (LoW+1)'(1);
    hi_ones = &t_q[TW-1:LoW];
    hi_zeros = ~(|t_q[TW-1:LoW]);
    // u >> 1 fits in OutW bits iff u's bits TW-1..OutW are equal. Carry out: the high
    // part is t's + 1 and u[OutW] = 0, so they are equal iff t's high bits are all ones;
    // no carry: the high part is t's and must equal u[OutW].
    fits = (lo_sum[LoW] | lo_sum[OutW]) ? hi_ones : hi_zeros;
  end
  always_ff @(posedge clk_i) begin
    clip_o <= ~fits;
    // out of range: saturate towards t's sign (u has the same sign there)
    if (fits) out_o <= lo_sum[OutW:1];
    else out_o <= {t_q[TW-1], {(OutW-1){~t_q[TW-1]}}};
  end
endmodule

// N-clock delay line (pipeline balancing), any N >= 0: N = 0 is a wire, longer lines are
// chains of rheo_delay_line (at most 33 clocks each).
module rheo_delay #(
  parameter int W = 32,
  parameter int N = 1
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  input  logic [W-1:0] d_i,
  output logic [W-1:0] q_o
);
  if (N == 0) begin : g_wire
    logic unused;
    assign unused = rst_ni ^ clk_i;
    assign q_o = d_i;
  end else begin : g_chain
    localparam int K = (N + 32) / 33;
    logic [W-1:0] seg [K+1];
    assign seg[0] = d_i;
    for (genvar i = 0; i < K; i++) begin : g_seg
      rheo_delay_line #(.W(W), .N(i < K - 1 ? 33 : N - 33 * (K - 1))) u_seg (
        .clk_i(clk_i), .rst_ni(rst_ni), .d_i(seg[i]), .q_o(seg[i+1]));
    end
    assign q_o = seg[K];
  end
endmodule

// One delay line of 1 <= N <= 33 clocks. Short lines are flip-flops; from 4 clocks on the
// line is a circular buffer in distributed RAM (one RAM16X1D / RAM32X1D per bit instead of
// N flip-flops; Yosys does not infer SRL16 for Virtex-II), read N - 1 clocks after the
// write into an output register.
module rheo_delay_line #(
  parameter int W = 32,
  parameter int N = 1
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  input  logic [W-1:0] d_i,
  output logic [W-1:0] q_o
);
  if (N < 4) begin : g_ff
    logic unused_rst;
    assign unused_rst = rst_ni;
    logic [W-1:0] q [N];
    always_ff @(posedge clk_i) begin
      q[0] <= d_i;
      for (int s = 1; s < N; s++) q[s] <= q[s-1];
    end
    assign q_o = q[N-1];
  end else begin : g_ram
    localparam int AW = (N - 1 <= 16) ? 4 : 5;
    if (N - 1 > 32) begin : g_depth_check
      $error("rheo_delay_line: N must be at most 33");
    end
    // distributed: Yosys would otherwise spend block RAMs, which the core's memories need
    (* ram_style = "distributed" *) logic [W-1:0] mem [2**AW];
    logic [AW-1:0] wr_q;
    logic [AW-1:0] rd;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) wr_q <= '0;
      else wr_q <= wr_q + AW'(1);
    end
    // written N - 1 clocks ago; N - 1 <= 2^AW - 1, so it is not yet overwritten
    assign rd = wr_q - AW'(N - 1);
    always_ff @(posedge clk_i) begin
      mem[wr_q] <= d_i;
      q_o <= mem[rd];
    end
  end
endmodule

// Bit length of an unsigned word (the position of its leading one plus one; 0 for 0), in
// two stages so that a wide word meets the clock: per 8-bit group whether it is non-zero and
// its own bit length, then the highest non-zero group's. Latency 2 (v_i is stage 0).
module rheo_bitlen #(
  parameter int InW = 40,
  parameter int NW = 6
) (
  input  logic           clk_i,
  input  logic [InW-1:0] v_i,
  output logic [NW-1:0]  n_o
);
  localparam int G = 8;
  localparam int NG = (InW + G - 1) / G;
  logic [NG*G-1:0] v;
  assign v = (NG*G)'(v_i);
  function automatic logic [3:0] len8(input logic [G-1:0] x);
    len8 = '0;
    for (int b = 0; b < G; b++) if (x[b]) len8 = 4'(b + 1);
  endfunction
  logic [NG-1:0] any_q;
  logic [3:0] len_q [NG];
  always_ff @(posedge clk_i) begin
    for (int k = 0; k < NG; k++) begin
      any_q[k] <= |v[k*G +: G];
      len_q[k] <= len8(v[k*G +: G]);
    end
  end
  logic [NW-1:0] n_w;
  always_comb begin
    n_w = '0;
    for (int k = 0; k < NG; k++) if (any_q[k]) n_w = NW'(k * G) + NW'(len_q[k]);
  end
  always_ff @(posedge clk_i) n_o <= n_w;
endmodule
