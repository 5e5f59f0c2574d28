// Material table of rheo_core: per material the packed TEM coefficients and flags (and,
// with MaxwellArms = K, each arm's gamma_j and k2t_j). Every lane reads it in the same clock, so
// each coefficient is a small LUT RAM with one registered read per lane (the edge pass's
// stage 2), written by the host only while idle. With SeriesDamper = 1 the damper's six
// coefficients (region MaterialDamper) follow the base ones, with StrainHardening = 1
// hardening's three (region MaterialHardening) after them, then the arms'.
module rheo_core_mem_mat #(
  parameter int Lanes = 1,
  parameter int MaxMaterials = 16,
  parameter int CoefW = 24,
  parameter int MaxwellArms = 0,
  parameter int SeriesDamper = 0,
  parameter int StrainHardening = 0,
  localparam int MIdxW = $clog2(MaxMaterials),
  localparam int NumDamper = (SeriesDamper != 0) ? rheo_consts_pkg::DamperCoefs : 0,
  localparam int NumBase = rheo_consts_pkg::MaterialCoefs + NumDamper +
                           ((StrainHardening != 0) ? rheo_consts_pkg::HardeningCoefs : 0),
  localparam int NumMat = rheo_consts_pkg::MaterialCoefs,  // region Material's coefficients
  localparam int NumArm = rheo_consts_pkg::MaterialArmCoefs,
  localparam int NumCoef = NumBase + NumArm * MaxwellArms,
  localparam int MFlagsW = rheo_consts_pkg::MatFlagsW,
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW
) (
  input  logic                          clk_i,
  input  logic                          host_we_i,
  input  logic [RegionW-1:0]            region_i,
  input  logic [IdxCountW-1:0]          index_i,  // material of the host's entry
  input  logic [FieldW-1:0]             field_i,
  input  logic [CoefW-1:0]              wdata_i,  // low bits of the host word
  input  logic [Lanes*MIdxW-1:0]        mat_i,    // lane j's material index
  output logic [Lanes*NumCoef*CoefW-1:0] coef_o,  // lane j: {arm K-1 .. arm 0, damper, base}
  output logic [Lanes*MFlagsW-1:0]      flags_o
);
  // One memory per coefficient (a column of the table): each is a MaxMaterials-word LUT RAM
  // with one write port and one read port per lane. A single two-dimensional array written
  // at a variable field would be one memory with NumCoef * Lanes read ports, which Yosys
  // maps by expanding every port over every word (it ran out of memory on the core with the
  // damper and eight arms).
  logic [MFlagsW-1:0] mat_flags [MaxMaterials];
  logic [CoefW-1:0] coef_q [Lanes][NumCoef];

  logic entry_ok;
  assign entry_ok = index_i < IdxCountW'(MaxMaterials);

  // Coefficient c's region and field: the base six (region Material, fields 0..5), the
  // damper's six (region MaterialDamper), hardening's three (region MaterialHardening), arm
  // k's two (region MaterialArm + 2 k).
  function automatic int coef_region(input int c);
    if (c < NumMat) coef_region = rheo_consts_pkg::RegionMaterial;
    else if (c < NumMat + NumDamper) coef_region = rheo_consts_pkg::RegionMaterialDamper;
    else if (c < NumBase) coef_region = rheo_consts_pkg::RegionMaterialHardening;
    else coef_region = rheo_consts_pkg::RegionMaterialArm + 2 * ((c - NumBase) / NumArm);
  endfunction
  function automatic int coef_field(input int c);
    if (c < NumMat) coef_field = c;
    else if (c < NumMat + NumDamper) coef_field = c - NumMat;
    else if (c < NumBase) coef_field = c - NumMat - NumDamper;
    else coef_field = (c - NumBase) % NumArm;
  endfunction

  for (genvar c = 0; c < NumCoef; c++) begin : g_col
    logic [CoefW-1:0] col [MaxMaterials];
    logic we;
    // an arm's field is one bit wide in its region (as the frame format writes it)
    if (c >= NumBase) begin : g_arm_field
      assign we = host_we_i && entry_ok && region_i == RegionW'(coef_region(c)) &&
                  field_i[0] == 1'(coef_field(c));
    end else begin : g_field
      assign we = host_we_i && entry_ok && region_i == RegionW'(coef_region(c)) &&
                  field_i == FieldW'(coef_field(c));
    end
    always_ff @(posedge clk_i) begin
      if (we) col[MIdxW'(index_i)] <= wdata_i;
      for (int j = 0; j < Lanes; j++) coef_q[j][c] <= col[mat_i[j*MIdxW +: MIdxW]];
    end
  end

  always_ff @(posedge clk_i) begin
    if (host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionMaterial) && entry_ok &&
        field_i >= FieldW'(NumMat))
      mat_flags[MIdxW'(index_i)] <= wdata_i[MFlagsW-1:0];
    for (int j = 0; j < Lanes; j++)
      flags_o[j*MFlagsW +: MFlagsW] <= mat_flags[mat_i[j*MIdxW +: MIdxW]];
  end

  for (genvar j = 0; j < Lanes; j++) begin : g_lane
    for (genvar c = 0; c < NumCoef; c++) begin : g_out
      assign coef_o[(j*NumCoef+c)*CoefW +: CoefW] = coef_q[j][c];
    end
  end
endmodule
