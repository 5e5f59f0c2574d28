// Read-back mux of rheo_core: the word of a READ command's entry from the memories' port A
// (particle x / p words, the edge slots' d or an arm's m). The controller keeps port A on the
// entry while idle, waits one clock for the registered read (StRFetch) and takes the word
// the clock after (StRLoad). The word's source is decoded from (region, bank, field) into
// one-hot selects registered in the fetch clock (they hold until the word is sent), so in
// the load clock the block-RAM outputs meet only an AND-OR.
// Flat vectors (lane j at [j*n +: n]): Yosys 0.23 mis-connects instance ports to elements
// of two-dimensional unpacked arrays.
module rheo_core_readback #(
  parameter int Lanes = 1,
  parameter int W = 32,
  parameter int MaxwellArms = 0,
  localparam int BW = (Lanes > 1) ? $clog2(Lanes) : 1,
  localparam int XpWords = rheo_consts_pkg::ParticleStateWords,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW,
  localparam int Arms = (MaxwellArms > 0) ? MaxwellArms : 1  // m words per lane
) (
  input  logic                     clk_i,
  input  logic [RegionW-1:0]       region_i,
  input  logic [BW-1:0]            bank_i,
  input  logic [FieldW-1:0]        field_i,
  input  logic                     particle_ok_i,
  input  logic                     edge_ok_i,
  input  logic [Lanes*XpWords*W-1:0] xp_a_i,  // per bank: port A of x / p
  input  logic [Lanes*W-1:0]       d_i,       // per lane: port A of d
  input  logic [Lanes*Arms*W-1:0]  m_i,       // per lane, per arm: port A of m
  output logic [W-1:0]             word_o
);
  logic [Lanes*XpWords-1:0] sel_xp_q;
  logic [Lanes-1:0] sel_d_q;
  logic [Lanes*Arms-1:0] sel_m_q;
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      for (int f = 0; f < XpWords; f++) begin
        sel_xp_q[j*XpWords + f] <= region_i == RegionW'(rheo_consts_pkg::RegionParticleState) &&
                                   particle_ok_i && bank_i == BW'(j) && field_i == FieldW'(f);
      end
      sel_d_q[j] <= region_i == RegionW'(rheo_consts_pkg::RegionEdgeLength) && edge_ok_i &&
                    bank_i == BW'(j);
      for (int k = 0; k < Arms; k++) begin
        sel_m_q[j*Arms + k] <= k < MaxwellArms &&
                               region_i == RegionW'(rheo_consts_pkg::RegionEdgeArm + 2 * k) &&
                               edge_ok_i && bank_i == BW'(j);
      end
    end
  end

  always_comb begin
    word_o = '0;
    for (int j = 0; j < Lanes; j++) begin
      for (int f = 0; f < XpWords; f++) begin
        if (sel_xp_q[j*XpWords + f]) word_o = word_o | xp_a_i[(j*XpWords + f)*W +: W];
      end
      if (sel_d_q[j]) word_o = word_o | d_i[j*W +: W];
      for (int k = 0; k < Arms; k++) begin
        if (sel_m_q[j*Arms + k]) word_o = word_o | m_i[(j*Arms + k)*W +: W];
      end
    end
  end
endmodule
