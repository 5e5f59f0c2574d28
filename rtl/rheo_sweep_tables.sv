// The sweep core's small tables, written by the host while idle: the index offsets of the
// implicit topology (registers, seen by every lane at once), the edge classes (natural
// length L and material of each class) and the mass classes (1/m as a packed
// coefficient). Each lane reads the class and mass tables through its own registered port
// (LUT RAM: one column per field, one read port per lane).
module rheo_sweep_tables #(
  parameter int Lanes = 1,
  parameter int W = 32,
  parameter int CoefW = 24,
  localparam int Offsets = rheo_consts_pkg::SweepOffsets,
  localparam int OffW = rheo_consts_pkg::SweepOffsetBits,
  localparam int Classes = rheo_consts_pkg::SweepEdgeClasses,
  localparam int ClsW = rheo_consts_pkg::SweepClassBits,
  localparam int Masses = rheo_consts_pkg::SweepMassClasses,
  localparam int MassW = rheo_consts_pkg::SweepMassBits,
  localparam int MIdxW = 4,
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW
) (
  input  logic                   clk_i,
  input  logic                   rst_ni,
  input  logic                   host_we_i,
  input  logic [RegionW-1:0]     region_i,
  input  logic [IdxCountW-1:0]   index_i,
  input  logic [FieldW-1:0]      field_i,
  input  logic [W-1:0]           wdata_i,
  output logic [Offsets*OffW-1:0] offsets_o,  // offset k at [k*OffW +: OffW]
  input  logic [Lanes*ClsW-1:0]  cls_i,       // lane j's class
  output logic [Lanes*W-1:0]     len_o,       // its L, one clock later
  output logic [Lanes*MIdxW-1:0] mat_o,       // and material
  input  logic [Lanes*MassW-1:0] mass_i,      // lane j's mass class
  output logic [Lanes*CoefW-1:0] minv_o       // its 1/m, one clock later
);
  logic [OffW-1:0] offset_q [Offsets];
  // Small tables: LUT RAM (a block RAM each would spend what the lanes' memories need).
  (* ram_style = "distributed" *) logic [W-1:0] len_col [Classes];
  (* ram_style = "distributed" *) logic [MIdxW-1:0] mat_col [Classes];
  (* ram_style = "distributed" *) logic [CoefW-1:0] minv_col [Masses];
  logic we_offset, we_len, we_mat, we_minv;
  assign we_offset = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionSweepOffset) &&
                     index_i < IdxCountW'(Offsets);
  assign we_len = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionSweepClass) &&
                  index_i < IdxCountW'(Classes) && field_i == FieldW'(0);
  assign we_mat = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionSweepClass) &&
                  index_i < IdxCountW'(Classes) && field_i == FieldW'(1);
  assign we_minv = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionSweepMass) &&
                   index_i < IdxCountW'(Masses);
  // The offsets have a reset: an unused offset must read 0 (no edge) in a core loaded with
  // fewer offsets than it has.
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      for (int k = 0; k < Offsets; k++) offset_q[k] <= '0;
    end else if (we_offset) begin
      offset_q[index_i[$clog2(Offsets)-1:0]] <= wdata_i[OffW-1:0];
    end
  end
  for (genvar k = 0; k < Offsets; k++) begin : g_off
    assign offsets_o[k*OffW +: OffW] = offset_q[k];
  end
  always_ff @(posedge clk_i) begin
    if (we_len) len_col[index_i[ClsW-1:0]] <= wdata_i;
    if (we_mat) mat_col[index_i[ClsW-1:0]] <= wdata_i[MIdxW-1:0];
    if (we_minv) minv_col[index_i[MassW-1:0]] <= wdata_i[CoefW-1:0];
    for (int j = 0; j < Lanes; j++) begin
      len_o[j*W +: W] <= len_col[cls_i[j*ClsW +: ClsW]];
      mat_o[j*MIdxW +: MIdxW] <= mat_col[cls_i[j*ClsW +: ClsW]];
      minv_o[j*CoefW +: CoefW] <= minv_col[mass_i[j*MassW +: MassW]];
    end
  end
endmodule
