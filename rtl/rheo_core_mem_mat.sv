// Material table of rheo_core: per material the packed TEM coefficients and flags (and,
// with MaxwellArms = K, each arm's gamma_j and k2t_j). Every lane reads it in the same clock, so it
// is a small LUT RAM with one registered read per lane (the edge pass's stage 2), written
// by the host only while idle. With SeriesDamper = 1 the damper's six coefficients
// (region MaterialDamper) follow the base ones.
module rheo_core_mem_mat #(
  parameter int Lanes = 1,
  parameter int MaxMaterials = 16,
  parameter int CoefW = 24,
  parameter int MaxwellArms = 0,
  parameter int SeriesDamper = 0,
  localparam int MIdxW = $clog2(MaxMaterials),
  localparam int NumBase = rheo_consts_pkg::MaterialCoefs +
                           ((SeriesDamper != 0) ? rheo_consts_pkg::DamperCoefs : 0),
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
  logic [CoefW-1:0] mat_coef [MaxMaterials][NumBase];
  logic [MFlagsW-1:0] mat_flags [MaxMaterials];
  logic [Lanes*NumBase*CoefW-1:0] coef_q;

  logic entry_ok;
  assign entry_ok = index_i < IdxCountW'(MaxMaterials);

  always_ff @(posedge clk_i) begin
    if (host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionMaterial) && entry_ok) begin
      if (field_i < FieldW'(NumMat)) mat_coef[MIdxW'(index_i)][32'(field_i)] <= wdata_i;
      else mat_flags[MIdxW'(index_i)] <= wdata_i[MFlagsW-1:0];
    end
    if (SeriesDamper != 0 && host_we_i &&
        region_i == RegionW'(rheo_consts_pkg::RegionMaterialDamper) && entry_ok &&
        field_i < FieldW'(rheo_consts_pkg::DamperCoefs))
      mat_coef[MIdxW'(index_i)][32'(field_i) + NumMat] <= wdata_i;
  end

  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      for (int c = 0; c < NumBase; c++)
        coef_q[(j*NumBase+c)*CoefW +: CoefW] <= mat_coef[mat_i[j*MIdxW +: MIdxW]][c];
      flags_o[j*MFlagsW +: MFlagsW] <= mat_flags[mat_i[j*MIdxW +: MIdxW]];
    end
  end

  if (MaxwellArms > 0) begin : g_arm
    localparam int NumArms = NumArm * MaxwellArms;  // coefficients of all arms
    // Arm k's coefficients at [k * NumArm + field]; region MaterialArm + 2 k writes them.
    logic [CoefW-1:0] mat_arm [MaxMaterials][NumArms];
    logic [Lanes*NumArms*CoefW-1:0] arm_q;
    always_ff @(posedge clk_i) begin
      for (int k = 0; k < MaxwellArms; k++) begin
        if (host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionMaterialArm + 2 * k) &&
            entry_ok)
          mat_arm[MIdxW'(index_i)][k * NumArm + 32'(field_i[0])] <= wdata_i;
      end
      for (int j = 0; j < Lanes; j++) begin
        for (int c = 0; c < NumArms; c++)
          arm_q[(j*NumArms+c)*CoefW +: CoefW] <= mat_arm[mat_i[j*MIdxW +: MIdxW]][c];
      end
    end
    for (genvar j = 0; j < Lanes; j++) begin : g_lane
      assign coef_o[j*NumCoef*CoefW +: NumCoef*CoefW] =
          {arm_q[j*NumArms*CoefW +: NumArms*CoefW], coef_q[j*NumBase*CoefW +: NumBase*CoefW]};
    end
  end else begin : g_no_arm
    for (genvar j = 0; j < Lanes; j++) begin : g_lane
      assign coef_o[j*NumCoef*CoefW +: NumCoef*CoefW] =
          coef_q[j*NumBase*CoefW +: NumBase*CoefW];
    end
  end
endmodule
