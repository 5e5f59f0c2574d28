// Reciprocal square root of an unsigned squared length, fully pipelined (one input per
// clock). l2 is normalised to M * 4^k with M in [2^30, 2^32) (m = M / 2^30 in [1, 4)),
// a 7-bit-addressed seed ROM gives y0 ~ 1/sqrt(m) in Q1.17, and RsqrtIterations
// Newton-Raphson steps y <- y (3 - m y^2) / 2 refine it in Q2.30 (3 multiplier stages
// each). Bits of l2 below the 32-bit mantissa are truncated. Relative error of y after
// two steps: below 2^-26 over [1, 4) (tests/hw/rsqrt_test.cpp).
// Latency: 2 + 3 * RsqrtIterations clocks. Mirrors rheo::hls::rsqrt_l2.
module rheo_rsqrt #(
  parameter int L2W = 68  // width of the unsigned squared length
) (
  input  logic           clk_i,
  input  logic [L2W-1:0] l2_i,          // squared length (any binary point)
  output logic [31:0]    mant_o,        // M
  output logic [31:0]    y_o,           // Y ~ 2^30 / sqrt(M / 2^30)
  output logic signed [7:0] k_o,        // l2 = M * 4^k
  output logic           degenerate_o   // l2 == 0
);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int Iter = rheo_consts_pkg::RsqrtIterations;
  localparam int Frac = rheo_consts_pkg::RsqrtFrac;
  localparam int IdxW = rheo_consts_pkg::RsqrtIndexBits;
  localparam int SeedW = rheo_consts_pkg::RsqrtSeedBits;
  // Stages: 0 normalise, 1 seed, then 3 per iteration.
  localparam int Stages = 2 + 3 * Iter;

  // ---- stage 0: normalisation (leading-one detection) ----
  logic [7:0] n;
  logic signed [8:0] two_k;
  logic [L2W-1:0] l2_norm;
  always_comb begin
    n = '0;
    for (int b = 0; b < L2W; b++) begin
      if (l2_i[b]) n = 8'(b + 1);
    end
    two_k = n[0] ? ($signed({1'b0, n}) - 9'sd31) : ($signed({1'b0, n}) - 9'sd32);
    if (two_k >= 0) l2_norm = l2_i >> two_k;
    else l2_norm = l2_i << (-two_k);
  end

  logic [31:0] mant_q [Stages];
  logic [31:0] y_q [Stages];
  logic signed [WideW-1:0] tmp_q [Stages];  // y^2, then 3 - m y^2, within an iteration
  logic signed [7:0] k_q [Stages];
  logic deg_q [Stages];

  always_ff @(posedge clk_i) begin
    mant_q[0] <= l2_norm[31:0];
    k_q[0] <= (n == 0) ? 8'sd0 : 8'(two_k >>> 1);
    deg_q[0] <= (n == 0);
    y_q[0] <= '0;
    tmp_q[0] <= '0;
    // stage 1: seed ROM
    mant_q[1] <= mant_q[0];
    k_q[1] <= k_q[0];
    deg_q[1] <= deg_q[0];
    y_q[1] <= 32'(rheo_consts_pkg::rsqrt_seed(mant_q[0][31 -: IdxW])) << (Frac - (SeedW - 1));
    tmp_q[1] <= '0;
  end

  // Newton-Raphson iterations: stage a y^2, stage b 3 - m y^2, stage c y (3 - m y^2) / 2.
  always_ff @(posedge clk_i) begin
    for (int it = 0; it < Iter; it++) begin
      for (int j = 0; j < 3; j++) begin
        mant_q[2+3*it+j] <= mant_q[1+3*it+j];
        k_q[2+3*it+j] <= k_q[1+3*it+j];
        deg_q[2+3*it+j] <= deg_q[1+3*it+j];
      end
      y_q[2+3*it] <= y_q[1+3*it];
      tmp_q[2+3*it] <= rheo_consts_pkg::round_shift(
          WideW'($signed({1'b0, y_q[1+3*it]})) * WideW'($signed({1'b0, y_q[1+3*it]})), Frac);
      y_q[3+3*it] <= y_q[2+3*it];
      tmp_q[3+3*it] <= (WideW'(3) <<< Frac) - rheo_consts_pkg::round_shift(
          WideW'($signed({1'b0, mant_q[2+3*it]})) * tmp_q[2+3*it], Frac);
      y_q[4+3*it] <= 32'(rheo_consts_pkg::round_shift(
          WideW'($signed({1'b0, y_q[3+3*it]})) * tmp_q[3+3*it], Frac + 1));
      tmp_q[4+3*it] <= '0;
    end
  end

  assign mant_o = mant_q[Stages-1];
  assign y_o = y_q[Stages-1];
  assign k_o = k_q[Stages-1];
  assign degenerate_o = deg_q[Stages-1];
endmodule
