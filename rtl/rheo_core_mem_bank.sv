// Particle bank of rheo_core: the state (x, p), the static words (x0, minv, flags) and the
// two force sums (start and end side) of the particles i with i % Lanes == this bank.
// A module of its own so that the ports of each physical memory, and so its RAMB16 /
// LUT RAM mapping, are written down in one place.
//
// Ports (every memory has at most two, both registered):
//   x / p (one rheo_ram_tdp per word):
//     A reads: the MPM pass's particle row, the edge pass's start particle, or the host's
//       read-back entry.
//     B reads the crossbar's end particle in the edge pass; it writes the MPM's result,
//       or a host word.
//   x0 / minv / flags (rheo_ram_sdp): A reads the MPM pass's row, B is the host's write.
//   force sums (rheo_force_acc): additions from the TEMs; read and cleared by the MPM pass.
module rheo_core_mem_bank #(
  parameter int W = 32,
  parameter int CoefW = 24,
  parameter int PDepth = 256,          // particles of this bank
  localparam int PAW = (PDepth > 1) ? $clog2(PDepth) : 1,
  localparam int AccW = rheo_consts_pkg::ForceAccW,
  localparam int XpWords = rheo_consts_pkg::ParticleStateWords,
  localparam int PFlagsW = rheo_consts_pkg::ParticleFlagsW,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW
) (
  input  logic                  clk_i,
  input  logic                  rst_ni,
  // Passes.
  input  logic                  mpm_phase_i,   // port A follows the particle row
  input  logic                  edge_phase_i,  // port A follows the start particle
  input  logic [PAW-1:0]        row_i,
  input  logic [PAW-1:0]        start_local_i,
  input  logic [PAW-1:0]        xbar_addr_i,   // end particle read through the crossbar
  // Host access.
  input  logic                  host_wdata_i,  // WRITE data phase: port B is the host's
  input  logic                  host_we_i,     // a host word for this bank's entry
  input  logic [PAW-1:0]        host_addr_i,
  input  logic [RegionW-1:0]    region_i,
  input  logic [FieldW-1:0]     field_i,
  input  logic [W-1:0]          wdata_i,
  // MPM results.
  input  logic                  mpm_valid_i,
  input  logic [PAW-1:0]        mpm_idx_i,
  input  logic [3*W-1:0]        mpm_x_i,
  input  logic [3*W-1:0]        mpm_p_i,
  // Words side by side ({p, x}): Yosys 0.23 mis-connects instance ports to elements of
  // two-dimensional unpacked arrays.
  output logic [XpWords*W-1:0]  xp_a_o,
  output logic [XpWords*W-1:0]  xp_b_o,
  output logic [3*W-1:0]        x0_o,
  output logic [CoefW-1:0]      minv_o,
  output logic [PFlagsW-1:0]    pflags_o,
  // Force sums.
  input  logic                  acc_s_valid_i,
  input  logic [PAW-1:0]        acc_s_addr_i,
  input  logic [3*AccW-1:0]     acc_s_val_i,
  input  logic                  acc_e_valid_i,
  input  logic [PAW-1:0]        acc_e_addr_i,
  input  logic [3*AccW-1:0]     acc_e_val_i,
  input  logic                  clear_i,
  input  logic [PAW-1:0]        clear_addr_i,
  output logic [3*AccW-1:0]     sum_s_o,
  output logic [3*AccW-1:0]     sum_e_o
);
  logic [PAW-1:0] xp_a_addr, xp_b_addr;
  assign xp_a_addr = mpm_phase_i ? row_i : edge_phase_i ? start_local_i : host_addr_i;
  assign xp_b_addr = mpm_valid_i ? mpm_idx_i : host_wdata_i ? host_addr_i : xbar_addr_i;

  logic state_we, static_we;
  assign state_we = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionParticleState);
  assign static_we = host_we_i && region_i == RegionW'(rheo_consts_pkg::RegionParticleStatic);

  logic [XpWords*W-1:0] xp_b_wdata;
  logic [XpWords-1:0] xp_b_we;
  assign xp_b_wdata = mpm_valid_i ? {mpm_p_i, mpm_x_i} : {XpWords{wdata_i}};
  for (genvar w = 0; w < XpWords; w++) begin : g_xp
    assign xp_b_we[w] = mpm_valid_i || (state_we && field_i == FieldW'(w));
    rheo_ram_tdp #(.Width(W), .Depth(PDepth)) u_xp (
      .clk_i(clk_i), .a_addr_i(xp_a_addr), .a_data_o(xp_a_o[w*W +: W]),
      .b_we_i(xp_b_we[w]), .b_addr_i(xp_b_addr), .b_data_i(xp_b_wdata[w*W +: W]),
      .b_data_o(xp_b_o[w*W +: W]));
  end

  for (genvar w = 0; w < 3; w++) begin : g_x0
    rheo_ram_sdp #(.Width(W), .Depth(PDepth)) u_x0 (
      .clk_i(clk_i), .a_addr_i(row_i), .a_data_o(x0_o[w*W +: W]),
      .b_we_i(static_we && field_i == FieldW'(w)), .b_addr_i(host_addr_i),
      .b_data_i(wdata_i));
  end
  rheo_ram_sdp #(.Width(CoefW), .Depth(PDepth)) u_minv (
    .clk_i(clk_i), .a_addr_i(row_i), .a_data_o(minv_o),
    .b_we_i(static_we && field_i == FieldW'(3)), .b_addr_i(host_addr_i),
    .b_data_i(wdata_i[CoefW-1:0]));
  rheo_ram_sdp #(.Width(PFlagsW), .Depth(PDepth)) u_pflags (
    .clk_i(clk_i), .a_addr_i(row_i), .a_data_o(pflags_o),
    .b_we_i(static_we && field_i == FieldW'(4)), .b_addr_i(host_addr_i),
    .b_data_i(wdata_i[PFlagsW-1:0]));

  rheo_force_acc #(.AccW(AccW), .Depth(PDepth)) u_sum_start (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .add_valid_i(acc_s_valid_i), .add_addr_i(acc_s_addr_i), .add_val_i(acc_s_val_i),
    .sum_addr_i(row_i), .sum_o(sum_s_o),
    .clear_i(clear_i), .clear_addr_i(clear_addr_i));
  rheo_force_acc #(.AccW(AccW), .Depth(PDepth)) u_sum_end (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .add_valid_i(acc_e_valid_i), .add_addr_i(acc_e_addr_i), .add_val_i(acc_e_val_i),
    .sum_addr_i(row_i), .sum_o(sum_e_o),
    .clear_i(clear_i), .clear_addr_i(clear_addr_i));
endmodule
