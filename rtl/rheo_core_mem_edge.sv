// Edge slot memories of one lane of rheo_core: per slot the packed record (valid, the
// volume element's two bits, end bank, end and start local addresses), the rest length L, the Voigt length d, the material
// index and, with MaxwellArms = K, the arms' extensions m_j. A module of its own so that each
// memory's two ports (and so its RAMB16 / LUT RAM mapping) can be read in one place.
//
// Ports of every memory (rheo_ram_sdp: A reads, B writes, both registered):
//   A: the edge pass reads row row_i, otherwise the host's read-back follows host_addr_i.
//   B: the TEM writes d (and every m_j) back at its result's row; otherwise the host writes.
module rheo_core_mem_edge #(
  parameter int W = 32,
  parameter int EDepth = 256,          // edge slots of this lane
  parameter int PAW = 8,               // local particle address bits
  parameter int MaxMaterials = 16,
  parameter int MaxwellArms = 0,
  localparam int EAW = (EDepth > 1) ? $clog2(EDepth) : 1,
  localparam int EBW = rheo_consts_pkg::EdgeBankBits,
  localparam int MIdxW = $clog2(MaxMaterials),
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW,
  // Record: {valid, element, second half, end bank, end local address, start local address}.
  localparam int RecW = 3 + EBW + 2 * PAW,
  localparam int ArmW = ((MaxwellArms > 0) ? MaxwellArms : 1) * W  // m words, arm j at [j*W +: W]
) (
  input  logic               clk_i,
  input  logic               tem_pass_i,   // read the row of the edge pass
  input  logic [EAW-1:0]     row_i,
  input  logic [EAW-1:0]     host_addr_i,  // the host's entry (local slot address)
  input  logic               host_we_i,    // a host word for this lane's slot host_addr_i
  input  logic [RegionW-1:0] region_i,
  input  logic [FieldW-1:0]  field_i,
  input  logic [W-1:0]       wdata_i,
  input  logic               wb_valid_i,   // TEM write-back of d and m
  input  logic [EAW-1:0]     wb_row_i,
  input  logic [W-1:0]       wb_d_i,
  input  logic [ArmW-1:0]    wb_m_i,
  output logic [RecW-1:0]    rec_o,
  output logic [W-1:0]       len_o,
  output logic [W-1:0]       d_o,
  output logic [MIdxW-1:0]   mat_o,
  output logic [ArmW-1:0]    m_o           // zero without arms
);
  logic [EAW-1:0] a_addr, b_addr;
  assign a_addr = tem_pass_i ? row_i : host_addr_i;
  assign b_addr = wb_valid_i ? wb_row_i : host_addr_i;

  logic edge_entry;
  assign edge_entry = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionEdge);
  logic rec_we, len_we, d_we, mat_we;
  assign rec_we = edge_entry && field_i == FieldW'(0);
  assign len_we = edge_entry && field_i == FieldW'(1);
  assign d_we = wb_valid_i || (edge_entry && field_i == FieldW'(2)) ||
                (host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionEdgeLength));
  assign mat_we = edge_entry && field_i == FieldW'(3);

  // Edge word 0 as the host packs it (hls/frame_format.hpp), cut to this core's widths.
  logic [RecW-1:0] rec_wdata;
  assign rec_wdata = {wdata_i[rheo_consts_pkg::EdgeValidBit],
                      wdata_i[rheo_consts_pkg::EdgeElementBit],
                      wdata_i[rheo_consts_pkg::EdgeSecondBit],
                      wdata_i[rheo_consts_pkg::EdgeEndBankShift +: EBW],
                      wdata_i[rheo_consts_pkg::EdgeEndLocalShift +: PAW],
                      wdata_i[PAW-1:0]};

  rheo_ram_sdp #(.Width(RecW), .Depth(EDepth)) u_rec (
    .clk_i(clk_i), .a_addr_i(a_addr), .a_data_o(rec_o),
    .b_we_i(rec_we), .b_addr_i(host_addr_i), .b_data_i(rec_wdata));
  rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_len (
    .clk_i(clk_i), .a_addr_i(a_addr), .a_data_o(len_o),
    .b_we_i(len_we), .b_addr_i(host_addr_i), .b_data_i(wdata_i));
  rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_d (
    .clk_i(clk_i), .a_addr_i(a_addr), .a_data_o(d_o),
    .b_we_i(d_we), .b_addr_i(b_addr), .b_data_i(wb_valid_i ? wb_d_i : wdata_i));
  rheo_ram_sdp #(.Width(MIdxW), .Depth(EDepth)) u_mat (
    .clk_i(clk_i), .a_addr_i(a_addr), .a_data_o(mat_o),
    .b_we_i(mat_we), .b_addr_i(host_addr_i), .b_data_i(wdata_i[MIdxW-1:0]));

  // One memory per arm: the host writes one arm's word at a time (its region).
  for (genvar k = 0; k < MaxwellArms; k++) begin : g_arm
    logic m_we;
    assign m_we = wb_valid_i ||
                  (host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionEdgeArm + 2 * k));
    rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_m (
      .clk_i(clk_i), .a_addr_i(a_addr), .a_data_o(m_o[k*W +: W]),
      .b_we_i(m_we), .b_addr_i(b_addr), .b_data_i(wb_valid_i ? wb_m_i[k*W +: W] : wdata_i));
  end
  if (MaxwellArms == 0) begin : g_no_arm
    assign m_o = '0;
    logic unused_m;
    assign unused_m = ^wb_m_i;
  end
endmodule
