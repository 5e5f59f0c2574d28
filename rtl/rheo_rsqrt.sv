// Reciprocal square root of the TEM's normalised squared length, fully pipelined (one
// input per clock), every product with B-bit operands (one MULT18X18 for B = 18).
// l2n (an exact sum of three squared B-bit mantissas) = m 2^(2k + parity) with m in [1, 2)
// rounded to a Q1.(B-2) operand; a 1024-entry seed ROM indexed by {parity, 9 fraction bits
// of m} gives y0 ~ 1/sqrt(m 2^parity) in Q0.17 (relative error <= 2^-11), and one
// Newton-Raphson step y = y0 + y0 (1 - m 2^parity y0^2) / 2 refines it in Q0.(B-1):
//   m y0 (rounded to an operand), m y0^2, eps = 1 - m 2^parity y0^2 (an operand with 8
//   more fractional bits than y), y0 eps.
// Measured relative error of y over every m and parity: below 1.2e-5 (2^-16.4;
// tests/hw/rsqrt_test.cpp).
// Stages (latency 11): 1 leading one, 2-3 m (shift, round), 4 seed ROM, 5 m y0,
// 6 round, 7 m y0^2, 8 eps, 9 eps operand, 10 y0 eps, 11 y. Multipliers: 3.
// Mirrors rheo::hls::rsqrt_l2 / rsqrt_mantissa.
module rheo_rsqrt #(
  parameter int B = 18,                 // operand width (rheo_consts_pkg::OperandBits)
  localparam int L2W = 2 * B            // l2n < 3 * 2^(2B-2) < 2^(2B)
) (
  input  logic                 clk_i,
  input  logic                 rst_ni,        // delay-line pointers only
  input  logic [L2W-1:0]       l2_i,          // l2n (unsigned)
  output logic signed [B-1:0]  mant_o,        // m, Q1.(B-2)
  output logic signed [B-1:0]  y_o,           // y, Q0.(B-1), 0 when degenerate
  output logic                 parity_o,      // l2n = m 2^(2k + parity)
  output logic [5:0]           k_o,
  output logic                 degenerate_o   // l2n == 0
);
  localparam int IdxW = rheo_consts_pkg::RsqrtIndexBits;
  localparam int SeedW = rheo_consts_pkg::RsqrtSeedBits;
  localparam int EpsFrac = B - 1 + rheo_consts_pkg::RsqrtEpsExtraFrac;
  localparam int PW = 2 * B;  // product width

  if (rheo_consts_pkg::RsqrtIterations != 1) begin : g_iter_check
    $error("rheo_rsqrt implements one Newton-Raphson step");
  end

  // ---- stage 1: n = bit length of l2n ----
  // Leading one in two levels, so the mapped logic stays shallow: within each group of G
  // bits the local bit length (a function of G inputs), and the group that holds the
  // leading one (no higher group has a bit set); n is an OR of the candidates, at most one
  // of which is non-zero, rather than a priority multiplexer chain.
  localparam int G = 6;
  localparam int NG = (L2W + G - 1) / G;
  logic [5:0] n_w;
  logic [NG*G-1:0] l2_pad;
  logic [NG-1:0] any_g;        // group g has a bit set
  logic [NG-1:0] higher_g;     // a group above g has a bit set
  logic [2:0] local_n [NG];    // bit length within group g (0 when empty)
  always_comb begin
    l2_pad = (NG * G)'(l2_i);
    for (int g = 0; g < NG; g++) begin
      any_g[g] = |l2_pad[g*G +: G];
      local_n[g] = 3'd0;
      for (int b = 0; b < G; b++) if (l2_pad[g*G + b]) local_n[g] = 3'(b + 1);
    end
    higher_g[NG-1] = 1'b0;
    for (int g = NG - 2; g >= 0; g--) higher_g[g] = higher_g[g+1] | any_g[g+1];
    n_w = '0;
    for (int g = 0; g < NG; g++)
      n_w = n_w | ((any_g[g] & ~higher_g[g]) ? 6'(g * G) + 6'(local_n[g]) : 6'd0);
  end
  logic [L2W-1:0] l2_1_q;
  logic [5:0] n_1_q;
  always_ff @(posedge clk_i) begin
    l2_1_q <= l2_i;
    n_1_q <= n_w;
  end

  // ---- stages 2-3: m = l2n 2^-(n - (B-1)), rounded, held below 2^(B-1) ----
  logic signed [B-1:0] m_3;
  logic unused_m_clip;
  // s = n - (B-1) >= -(B-1): biased by MaxLeft = B - 1 the shift amount is n itself
  rheo_round_shift #(.InW(L2W + 1), .OutW(B), .ShiftW(6), .MaxLeft(B - 1)) u_m (
    .clk_i (clk_i),
    .v_i   ($signed({1'b0, l2_1_q})),
    .sb_i  (n_1_q),
    .out_o (m_3),
    .clip_o(unused_m_clip)
  );
  // parity and k of n - 1 (0 for l2n == 0), delayed to stage 3
  logic [6:0] pk_1, pk_3;  // {degenerate, k, parity}
  always_comb begin
    if (n_1_q == 0) pk_1 = 7'b1_00000_0;
    else pk_1 = {1'b0, 5'((n_1_q - 6'd1) >> 1), n_1_q[0] ^ 1'b1};
  end
  rheo_delay #(.W(7), .N(2)) u_pk_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(pk_1), .q_o(pk_3));

  // ---- stage 4: seed ROM ----
  logic signed [B-1:0] m_q [4:9];
  logic [6:0] pk_q [4:11];
  logic signed [B-1:0] y0_q [4:10];
  always_ff @(posedge clk_i) begin
    m_q[4] <= m_3;
    pk_q[4] <= pk_3;
    y0_q[4] <= B'(rheo_consts_pkg::rsqrt_seed({pk_3[0], m_3[B-3 -: IdxW-1]})) <<< (B - 1 - SeedW);
    for (int s = 5; s <= 9; s++) m_q[s] <= m_q[s-1];
    for (int s = 5; s <= 11; s++) pk_q[s] <= pk_q[s-1];
    for (int s = 5; s <= 10; s++) y0_q[s] <= y0_q[s-1];
  end

  // ---- stages 5-11: one Newton-Raphson step ----
  logic signed [PW-1:0] my_prod_q, my2_q, corr_q;
  logic signed [B-1:0] my_q, eps_q, y_q;
  logic signed [PW+1:0] eps_wide_q;
  logic signed [PW+1:0] eps_round_w;
  logic signed [PW+EpsFrac:0] y_new_w;
  logic eps_fits, y_fits;
  always_comb begin
    eps_round_w = (eps_wide_q + ((PW+2)'(1) <<< (2 * B - 4 - EpsFrac))) >>> (2 * B - 3 - EpsFrac);
    // y0 + round(y0 eps 2^-(EpsFrac+1)) as one sum: y0 2^(EpsFrac+1) + y0 eps + half
    y_new_w = ((PW+EpsFrac+1)'(y0_q[10]) <<< (EpsFrac + 1)) + (PW+EpsFrac+1)'(corr_q) +
              ((PW+EpsFrac+1)'(1) <<< EpsFrac);
    y_new_w = y_new_w >>> (EpsFrac + 1);
    // range checks on the bits above the operand (no comparator chains)
    eps_fits = (&eps_round_w[PW+1:B-1]) | ~(|eps_round_w[PW+1:B-1]);
    y_fits = ~(|y_new_w[PW+EpsFrac:B-1]);  // y_new > 0
  end
  always_ff @(posedge clk_i) begin
    my_prod_q <= m_q[4] * y0_q[4];                                   // stage 5
    my_q <= B'((my_prod_q + (PW'(1) <<< (B - 2))) >>> (B - 1));      // stage 6
    my2_q <= my_q * y0_q[6];                                         // stage 7
    eps_wide_q <= ((PW+2)'(1) <<< (2 * B - 3)) -                     // stage 8
                  ((PW+2)'(my2_q) <<< pk_q[7][0]);
    if (eps_fits) eps_q <= eps_round_w[B-1:0];                       // stage 9
    else eps_q <= {eps_round_w[PW+1], {(B-1){~eps_round_w[PW+1]}}};
    corr_q <= y0_q[9] * eps_q;                                       // stage 10
    if (pk_q[10][6]) y_q <= '0;                                      // stage 11
    else if (!y_fits) y_q <= {1'b0, {(B-1){1'b1}}};
    else y_q <= y_new_w[B-1:0];
  end

  logic signed [B-1:0] m_11;
  rheo_delay #(.W(B), .N(2)) u_m_d (.clk_i(clk_i), .rst_ni(rst_ni), .d_i(m_q[9]), .q_o(m_11));
  assign mant_o = m_11;
  assign y_o = y_q;
  assign parity_o = pk_q[11][0];
  assign k_o = {1'b0, pk_q[11][5:1]};
  assign degenerate_o = pk_q[11][6];
endmodule
