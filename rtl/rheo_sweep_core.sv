// The sweep core: the paper's 15 x 15 x 16 model (seed 000) on one XC2V6000. It keeps only
// what a sweep in particle order needs (docs/sweep_core.md, hls/sweep_format.hpp):
//   - Lanes lanes, each owning a slab of consecutive particles (rheo_sweep_lane): every edge
//     runs from its lower to its higher particle and belongs to the lane of its end; a lane
//     sweeps its ghost particles' edges into the slab (cross edges), then its own particles
//     and their edges inside the slab, one slot per clock;
//   - implicit topology: an edge's end is its start plus one of SweepOffsets offsets, a
//     particle's static word says which (rheo_sweep_enum);
//   - the Voigt lengths stream through board SRAM, two ZBT devices per lane (IDT71V3556,
//     rheo_zbt_port): one read and one written each step, swapped at every step's end;
//   - a particle's MPM runs as soon as the sweep has passed it; the step ends one pipeline
//     after the slowest lane's last slot: max over lanes of (start delay + slots) +
//     SweepDrainCycles clocks (hls::sweep_cycles), nothing depending on the data.
// The TEM and MPM are rheo_core's (rheo_tem, rheo_mpm), the material table too, so the arithmetic is the same and the words equal hls::core_step's on
// the model with every edge oriented from its lower to its higher particle
// (hls::sweep_step).
//
// Files: rheo_sweep_ctrl.sv (commands, step), rheo_sweep_lane.sv (a lane's datapath and
// memories), rheo_sweep_enum.sv (a lane's stream), rheo_sweep_end_sums.sv (end-side force
// sums), rheo_sweep_tables.sv (offsets, classes, masses), rheo_zbt_port.sv (an SRAM
// device's pins). rheo_sweep_tb.sv adds the SRAM devices for Verilator.
module rheo_sweep_core #(
  parameter int Lanes = 5,
  parameter int SlabDepth = 1024,  // particles per lane
  parameter int GhostDepth = 256,  // ghost particles per lane
  parameter int Window = 512,      // open end-side force sums per lane
  parameter int W = 32,
  localparam int CoefW = rheo_consts_pkg::CoefW,
  localparam int NW = rheo_consts_pkg::ZbtAddrBits,
  localparam int DW = rheo_consts_pkg::ZbtWordBits,
  localparam int Devs = 2 * Lanes  // SRAM devices: lane j's are 2 j and 2 j + 1
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic [W-1:0]     s_axis_tdata,
  input  logic             s_axis_tvalid,
  output logic             s_axis_tready,
  input  logic             s_axis_tlast,
  output logic [W-1:0]     m_axis_tdata,
  output logic             m_axis_tvalid,
  input  logic             m_axis_tready,
  output logic             m_axis_tlast,
  output logic             busy_o,
  output logic [Devs*NW-1:0] zbt_a_o,
  output logic [Devs-1:0]    zbt_ce_n_o,
  output logic [Devs-1:0]    zbt_we_n_o,
  output logic [Devs*DW-1:0] zbt_d_o,
  output logic [Devs-1:0]    zbt_d_oe_o,
  input  logic [Devs*DW-1:0] zbt_q_i
);
  localparam int SAW = $clog2(SlabDepth);
  localparam int GAW = $clog2(GhostDepth);
  localparam int LW = (Lanes > 1) ? $clog2(Lanes) : 1;
  localparam int DelayW = rheo_consts_pkg::IdxCountW;
  localparam int Offsets = rheo_consts_pkg::SweepOffsets;
  localparam int OffW = rheo_consts_pkg::SweepOffsetBits;
  localparam int StatW = rheo_consts_pkg::SweepStaticBits;
  localparam int ClsW = rheo_consts_pkg::SweepClassBits;
  localparam int MassW = rheo_consts_pkg::SweepMassBits;
  localparam int SumW = rheo_consts_pkg::SweepSumBits;
  localparam int NumCoef = rheo_consts_pkg::MaterialCoefs;
  localparam int MFlagsW = rheo_consts_pkg::MatFlagsW;
  localparam int MIdxW = 4;
  localparam int XpW = 6 * W;
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW;
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits;
  localparam int FieldW = rheo_consts_pkg::EntryFieldW;

  if (W != rheo_consts_pkg::Width) begin : g_check
    $error("rheo_sweep_core: W must match rheo_consts_pkg");
  end
  if (Lanes < 1 || Lanes > rheo_consts_pkg::SweepMaxLanes) begin : g_lanes_check
    $error("rheo_sweep_core: Lanes must be 1..SweepMaxLanes");
  end
  if (Window < 2 * (1 << rheo_consts_pkg::SweepOffsetBits)) begin : g_window_check
    $error("rheo_sweep_core: the window must hold a particle's sums from its first edge to its MPM");
  end

  // ---------------------------------------------------------------- controller
  logic host_we, xp_we, stat_we, ghost_we, zbt_valid, zbt_we, idle, go;
  logic step_end, mixed, acc_clear;
  logic [RegionW-1:0] region;
  logic [FieldW-1:0] field;
  logic [IdxCountW-1:0] index;
  logic [W-1:0] wdata, read_word;
  logic [LW-1:0] lane_sel;
  logic [SAW-1:0] local_addr;
  logic [XpW-1:0] xp_wdata;
  logic [GAW-1:0] ghost_addr;
  logic [NW:0] zbt_addr;  // a slot's word: device (bit 0) and address
  logic [DW-1:0] zbt_wdata;
  logic [Lanes-1:0] done;
  logic [Lanes*(SAW+1)-1:0] count;
  logic [Lanes*(GAW+1)-1:0] ghost;
  logic [Lanes*DelayW-1:0] delay;
  logic [3*W-1:0] gravity;
  logic floor_en, plate_en, hold_en, prev_valid;
  logic [W-1:0] plate_z, plate_prev;
  logic [31:0] lane_flags;
  logic [rheo_consts_pkg::PlateAccW-1:0] plate_acc;
  rheo_sweep_ctrl #(.Lanes(Lanes), .SlabDepth(SlabDepth), .GhostDepth(GhostDepth), .W(W),
                    .DelayW(DelayW)) u_ctrl (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast), .busy_o(busy_o),
    .host_we_o(host_we), .region_o(region), .field_o(field), .index_o(index), .wdata_o(wdata),
    .lane_o(lane_sel), .local_o(local_addr), .xp_we_o(xp_we), .stat_we_o(stat_we),
    .xp_wdata_o(xp_wdata), .ghost_we_o(ghost_we), .ghost_addr_o(ghost_addr),
    .zbt_valid_o(zbt_valid), .zbt_we_o(zbt_we), .zbt_addr_o(zbt_addr), .zbt_wdata_o(zbt_wdata),
    .read_word_i(read_word), .idle_o(idle), .go_o(go), .step_end_o(step_end), .mixed_o(mixed),
    .acc_clear_o(acc_clear), .done_i(done),
    .count_o(count), .ghost_o(ghost), .delay_o(delay), .gravity_o(gravity),
    .floor_en_o(floor_en), .plate_en_o(plate_en), .plate_z_o(plate_z), .hold_en_o(hold_en),
    .prev_valid_o(prev_valid),
    .plate_prev_o(plate_prev), .lane_flags_i(lane_flags), .plate_acc_i(plate_acc));

  // ---------------------------------------------------------------- tables
  logic [Offsets*OffW-1:0] offsets;
  logic [Lanes*ClsW-1:0] cls;
  logic [Lanes*W-1:0] len;
  logic [Lanes*MIdxW-1:0] cls_mat, mat;
  logic [Lanes*MassW-1:0] mass;
  logic [Lanes*CoefW-1:0] minv;
  logic [Lanes*NumCoef*CoefW-1:0] coef;
  logic [Lanes*MFlagsW-1:0] mflags;
  rheo_sweep_tables #(.Lanes(Lanes), .W(W), .CoefW(CoefW)) u_tables (
    .clk_i(clk_i), .rst_ni(rst_ni), .host_we_i(host_we), .region_i(region), .index_i(index),
    .field_i(field), .wdata_i(wdata), .offsets_o(offsets), .cls_i(cls), .len_o(len),
    .mat_o(cls_mat), .mass_i(mass), .minv_o(minv));
  rheo_core_mem_mat #(.Lanes(Lanes), .MaxMaterials(16), .CoefW(CoefW)) u_mat (
    .clk_i(clk_i), .host_we_i(host_we), .region_i(region), .index_i(index), .field_i(field),
    .wdata_i(wdata[CoefW-1:0]), .mat_i(mat), .coef_o(coef), .flags_o(mflags));

  // ---------------------------------------------------------------- lanes
  logic [SAW-1:0] prev_stat_addr [Lanes];
  logic [StatW-1:0] next_stat [Lanes];
  logic [StatW-1:0] stat_rdata [Lanes];
  logic gxo_we [Lanes];
  logic [GAW-1:0] gxo_addr [Lanes];
  logic [XpW-1:0] gxo_wdata [Lanes];
  logic [GAW-1:0] gsn_raddr [Lanes];
  logic [3*SumW-1:0] gs_rdata [Lanes];
  logic [GAW:0] xread [Lanes], xdone [Lanes], gxw [Lanes], gsr [Lanes];
  logic [XpW-1:0] xp_rdata [Lanes];
  logic [DW-1:0] zbt_rdata [Lanes];
  logic [Lanes-1:0] plate_valid;
  logic [Lanes*W-1:0] plate_f;
  logic [31:0] flags [Lanes];
  for (genvar j = 0; j < Lanes; j++) begin : g_lane
    localparam bit Below = j > 0;
    localparam bit Above = j + 1 < Lanes;
    localparam int JB = Below ? j - 1 : 0;  // the lane below (a valid index)
    localparam int JA = Above ? j + 1 : j;  // the lane above
    // The ghost copy: written by the lane below's MPM in a step, by the host while idle.
    logic gx_we;
    logic [GAW-1:0] gx_addr;
    logic [XpW-1:0] gx_wdata;
    always_comb begin
      if (idle) begin
        gx_we = Below && ghost_we && 32'(lane_sel) == JB;
        gx_addr = ghost_addr;
        gx_wdata = xp_wdata;
      end else begin
        gx_we = Below && gxo_we[JB];
        gx_addr = gxo_addr[JB];
        gx_wdata = gxo_wdata[JB];
      end
    end
    rheo_sweep_lane #(
      .W(W), .CoefW(CoefW), .SlabDepth(SlabDepth), .GhostDepth(GhostDepth), .Window(Window),
      .HasGhost(Below ? 1 : 0), .DelayW(DelayW)
    ) u_lane (
      .clk_i(clk_i), .rst_ni(rst_ni), .go_i(go), .step_end_i(step_end), .mixed_i(mixed),
      .idle_i(idle),
      .done_o(done[j]),
      .count_i(count[j*(SAW+1) +: SAW+1]), .ghost_i(ghost[j*(GAW+1) +: GAW+1]),
      .delay_i(delay[j*DelayW +: DelayW]),
      .prev_count_i(Below ? count[JB*(SAW+1) +: SAW+1] : '0),
      .next_ghost_i(Above ? ghost[JA*(GAW+1) +: GAW+1] : '0),
      .offsets_i(offsets),
      .prev_stat_addr_o(prev_stat_addr[j]), .prev_stat_i(Below ? next_stat[JB] : '0),
      .next_stat_addr_i(Above ? prev_stat_addr[JA] : '0), .next_stat_o(next_stat[j]),
      .gx_we_i(gx_we), .gx_addr_i(gx_addr), .gx_wdata_i(gx_wdata),
      .gxo_we_o(gxo_we[j]), .gxo_addr_o(gxo_addr[j]), .gxo_wdata_o(gxo_wdata[j]),
      .gs_raddr_i(Below ? gsn_raddr[JB] : '0), .gs_rdata_o(gs_rdata[j]),
      .gsn_raddr_o(gsn_raddr[j]), .gsn_rdata_i(Above ? gs_rdata[JA] : '0),
      .xread_o(xread[j]), .xdone_o(xdone[j]),
      .next_xread_i(Above ? xread[JA] : '0), .next_xdone_i(Above ? xdone[JA] : '0),
      .gxw_o(gxw[j]), .gsr_o(gsr[j]),
      .prev_gxw_i(Below ? gxw[JB] : '0), .prev_gsr_i(Below ? gsr[JB] : '0),
      .cls_o(cls[j*ClsW +: ClsW]), .len_i(len[j*W +: W]),
      .cls_mat_i(cls_mat[j*MIdxW +: MIdxW]), .mat_o(mat[j*MIdxW +: MIdxW]),
      .coef_i(coef[j*NumCoef*CoefW +: NumCoef*CoefW]), .mflags_i(mflags[j*MFlagsW +: MFlagsW]),
      .mass_o(mass[j*MassW +: MassW]), .minv_i(minv[j*CoefW +: CoefW]),
      .gravity_i(gravity), .plate_z_i(plate_z), .plate_en_i(plate_en), .floor_en_i(floor_en),
      .hold_en_i(hold_en), .prev_valid_i(prev_valid), .plate_prev_i(plate_prev),
      .plate_valid_o(plate_valid[j]), .plate_f_o(plate_f[j*W +: W]), .flags_o(flags[j]),
      .host_addr_i(local_addr), .host_xp_we_i(xp_we && 32'(lane_sel) == j),
      .host_xp_wdata_i(xp_wdata), .host_xp_rdata_o(xp_rdata[j]),
      .host_stat_we_i(stat_we && 32'(lane_sel) == j), .host_stat_wdata_i(wdata[StatW-1:0]),
      .host_stat_rdata_o(stat_rdata[j]),
      .host_zbt_valid_i(zbt_valid && 32'(lane_sel) == j), .host_zbt_we_i(zbt_we),
      .host_zbt_addr_i(zbt_addr), .host_zbt_wdata_i(zbt_wdata), .host_zbt_rdata_o(zbt_rdata[j]),
      .zbt_a_o(zbt_a_o[2*j*NW +: 2*NW]), .zbt_ce_n_o(zbt_ce_n_o[2*j +: 2]),
      .zbt_we_n_o(zbt_we_n_o[2*j +: 2]), .zbt_d_o(zbt_d_o[2*j*DW +: 2*DW]),
      .zbt_d_oe_o(zbt_d_oe_o[2*j +: 2]), .zbt_q_i(zbt_q_i[2*j*DW +: 2*DW]));
  end
  always_comb begin
    lane_flags = '0;
    for (int j = 0; j < Lanes; j++) lane_flags |= flags[j];
  end

  rheo_sweep_plate_acc #(.Lanes(Lanes), .W(W)) u_plate_acc (
    .clk_i(clk_i), .start_i(acc_clear), .valid_i(plate_valid), .plate_f_i(plate_f), .acc_o(plate_acc));

  // ---------------------------------------------------------------- read-back
  // The word of the entry the controller reads (memories read in the clock before), in two
  // registered steps: each lane's field and region first, right behind its block RAMs'
  // outputs, then the lane. One wide multiplexer behind the block RAMs would not fit a clock.
  logic [W-1:0] lane_word_q [Lanes];
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      unique case (region)
        RegionW'(rheo_consts_pkg::RegionParticleState): lane_word_q[j] <= xp_rdata[j][field*W +: W];
        RegionW'(rheo_consts_pkg::RegionSweepParticle): lane_word_q[j] <= W'(stat_rdata[j]);
        RegionW'(rheo_consts_pkg::RegionEdgeLength): lane_word_q[j] <= zbt_rdata[j][W-1:0];
        RegionW'(rheo_consts_pkg::RegionSweepEdge):
          lane_word_q[j] <= field == '0 ? zbt_rdata[j][W-1:0] : W'(zbt_rdata[j][DW-1:W]);
        default: lane_word_q[j] <= '0;
      endcase
    end
  end
  always_ff @(posedge clk_i) begin
    read_word <= '0;
    for (int j = 0; j < Lanes; j++)
      if (32'(lane_sel) == j) read_word <= lane_word_q[j];
  end
endmodule
