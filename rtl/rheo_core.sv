// Rheological-object core: particle and edge state in on-chip memories, Lanes parallel
// TEM and MPM lanes, and an AXI4-Stream style command interface (format in
// hls/frame_format.hpp, constants in rheo_consts_pkg).
//
// Partitioning: particle i lives in bank i % Lanes at local address i / Lanes; edge slot t
// (host index) belongs to lane t % Lanes, row t / Lanes. The host (make_core_image)
// puts every edge in a slot of the lane whose bank holds its start particle and
// schedules the rows so that the end particles of one row lie in pairwise different banks
// (empty slots are bubbles). After reset the core clears its force sums (MaxParticles / Lanes
// clocks, input not ready). The command FSM keeps bank / local counters (a 24-clock
// shift-subtract division turns a command's start index into them).
//
// One step (after the plate-height word arrives):
//   edge pass: row r = 0 .. R-1; lane j reads slot (r, j), its start particle from its own
//              bank (port A) and its end particle through an L x L crossbar (port B of
//              the end's bank), runs its TEM, writes d (and the arm's m) back and adds +F
//              to the start particle's sum and -F to the end particle's sum (one
//              accumulator memory per bank for each side, read-modify-write with
//              forwarding, rheo_force_acc). A row with two ends in one bank raises
//              StatusScheduleConflict.
//   drain:     TemDrain clocks until the last sums are written.
//   MPM pass:  row a = 0 .. ceil(N / Lanes)-1; lane b reads particle a of its bank (x, p,
//              x0, minv, flags and both sums), clears the sums for the next step, runs its
//              MPM, writes x and p back and adds its plate force to the wide accumulator.
//   drain:     MpmDrain clocks until the last particle is written; then the plate-force
//              word is sent.
// Compute clocks per step (counted in status word 2):
//   max(R, 1) + TemDrain + ceil(N / Lanes) + MpmDrain       (host: cycles_per_step_formula)
// Sums are exact (ForceAccW bits, saturated once when narrowed for the MPM), so neither
// the schedule nor the lane count changes any bit (rheo::hls::core_step sums the same way).
//
// Memories: every physical memory has at most two ports, both registered (RAMB16 or LUT
// RAM): per bank x/p (A: TEM start read, MPM read, read-back; B: crossbar end read, MPM
// write, host write), x0/minv/flags and the two force sums (A: read, B: write); per lane
// the edge slots (A: edge pass read, read-back; B: TEM write-back, host write). The
// 16-entry material table is read by every lane (LUT RAM).
// MaxwellArm = 1 builds the variant with the parallel Maxwell arm in every TEM: per edge
// slot the arm's extension m (region EdgeArm, read and written like d) and per material
// gamma and k2t (region MaterialArm). Same cycles per step. MaxwellArm = 0 is the baseline
// core (the arm regions are refused as bad commands).
module rheo_core #(
  parameter int Lanes = 1,              // parallel TEM/MPM lanes and banks (1..4)
  parameter int MaxParticles = 4096,    // particle memory depth (all banks)
  parameter int MaxEdges = 65536,       // edge slots (all lanes, bubbles included)
  parameter int MaxMaterials = 16,      // material table depth
  parameter int W = 32,                 // stream and state word width
  parameter int CoefW = 24,             // packed coefficient width
  parameter int MaxwellArm = 0          // 1: TEMs with the parallel Maxwell arm
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  input  logic [W-1:0] s_axis_tdata,
  input  logic         s_axis_tvalid,
  output logic         s_axis_tready,
  input  logic         s_axis_tlast,    // not interpreted: the header gives the length
  output logic [W-1:0] m_axis_tdata,
  output logic         m_axis_tvalid,
  input  logic         m_axis_tready,
  output logic         m_axis_tlast,
  output logic         busy_o           // a step is being computed
);
  localparam int PDepth = (MaxParticles + Lanes - 1) / Lanes;  // particles per bank
  localparam int EDepth = (MaxEdges + Lanes - 1) / Lanes;      // edge slots per lane
  localparam int PAW = (PDepth > 1) ? $clog2(PDepth) : 1;
  localparam int EAW = (EDepth > 1) ? $clog2(EDepth) : 1;
  localparam int BW = (Lanes > 1) ? $clog2(Lanes) : 1;         // bank index
  localparam int EBW = rheo_consts_pkg::EdgeBankBits;          // end bank as the host sends it
  localparam int MIdxW = $clog2(MaxMaterials);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int AccW = rheo_consts_pkg::ForceAccW;
  localparam int SumW = AccW + 1;  // start sum + end sum
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW;
  localparam int TemDrain = rheo_consts_pkg::TemDrain;
  localparam int MpmDrain = rheo_consts_pkg::MpmDrain;
  localparam int NumCoef = (MaxwellArm != 0) ? 8 : 6;
  localparam int CoreRegions =
      (MaxwellArm != 0) ? rheo_consts_pkg::NumRegions : rheo_consts_pkg::NumBaseRegions;
  // Edge slot record: {valid, end bank, end local address, start local address}.
  localparam int RecW = 1 + EBW + 2 * PAW;
  // Carried through the TEM: {row, start local, end bank, end local}.
  localparam int TemIdxW = EAW + PAW + BW + PAW;
  localparam int IdxCountW = 24;  // command counts and indices

  if (W != rheo_consts_pkg::Width || CoefW != rheo_consts_pkg::CoefW) begin : g_check
    $error("rheo_core: W/CoefW must match rheo_consts_pkg");
  end
  if (Lanes < 1 || Lanes > 4) begin : g_lanes_check
    $error("rheo_core: Lanes must be 1..4");
  end
  if (PAW > rheo_consts_pkg::EdgeLocalBits) begin : g_depth_check
    $error("rheo_core: particles per bank exceed the edge word's local address field");
  end

  // ---------------------------------------------------------------- registers
  logic [IdxCountW-1:0] num_particles_q, edge_rows_q;
  logic [W-1:0] gravity_q [3];
  logic floor_en_q, plate_en_q;
  logic [W-1:0] plate_z_q;
  // Hold while pushing: a particle the plate held in the previous step sits exactly at
  // that step's plate height, so the previous height (valid from the second step after a
  // control write) stands in for a held bit per particle.
  logic plate_hold_en_q, plate_prev_valid_q;
  logic [W-1:0] plate_prev_q;
  logic [31:0] status_q, step_count_q, cycle_count_q;
  logic [CoefW-1:0] mat_coef [MaxMaterials][6];
  logic [1:0] mat_flags [MaxMaterials];

  typedef enum logic [4:0] {
    StClearSums, StIdle, StWStart, StWData, StRStart, StDivide, StRFetch, StRLoad, StRSend,
    StStatFetch, StStatSend, StRunPlate, StTem, StTemDrain, StMpm, StMpmDrain, StForceOut
  } state_e;
  state_e state_q;
  logic reading_q;                // the command being decoded is a READ
  logic [3:0] region_q;
  logic [IdxCountW-1:0] count_q;  // entries (or steps) remaining
  logic [IdxCountW-1:0] index_q;  // current entry
  logic [IdxCountW-1:0] local_q;  // current entry's local address (index_q / Lanes)
  logic [BW-1:0] bank_q;          // current entry's bank or lane (index_q % Lanes)
  logic [IdxCountW-1:0] div_num_q;
  logic [BW-1:0] div_rem_q;       // remainder so far (< Lanes)
  logic [4:0] div_step_q;
  logic [2:0] field_q;            // word within the entry
  logic clear_q;                  // status: clear after reading
  logic [IdxCountW-1:0] row_q;    // edge row / particle row of the passes
  logic [IdxCountW-1:0] base_q;   // first particle index of the particle row
  // Wide enough for the longer of the two drains (they follow the module latencies).
  localparam int DrainW = $clog2((TemDrain > MpmDrain ? TemDrain : MpmDrain) + 1);
  logic [DrainW-1:0] drain_q;
  logic [W-1:0] out_data_q;
  logic out_valid_q, out_last_q;
  logic signed [PlateAccW-1:0] plate_acc_q;

  // ---------------------------------------------------------------- stream handshakes
  logic in_fire, out_fire;
  assign s_axis_tready = (state_q == StIdle) || (state_q == StWStart) || (state_q == StWData) ||
                         (state_q == StRStart) || (state_q == StRunPlate);
  assign in_fire = s_axis_tvalid && s_axis_tready;
  assign out_fire = out_valid_q && m_axis_tready;
  assign m_axis_tdata = out_data_q;
  assign m_axis_tvalid = out_valid_q;
  assign m_axis_tlast = out_last_q;
  assign busy_o = (state_q == StTem) || (state_q == StTemDrain) || (state_q == StMpm) ||
                  (state_q == StMpmDrain);

  // Index of an entry's last word, registered with the command's region so that the
  // word-count lookup and its subtraction stay off the FSM's next-state path.
  logic [2:0] last_field_q;
  logic entry_done;
  assign entry_done = (field_q == last_field_q);

  logic host_we;
  assign host_we = (state_q == StWData) && in_fire;
  logic host_particle_ok, host_edge_ok;
  assign host_particle_ok = local_q < IdxCountW'(PDepth);
  assign host_edge_ok = local_q < IdxCountW'(EDepth);
  logic edge_phase, mpm_phase;
  assign edge_phase = (state_q == StTem) || (state_q == StTemDrain);
  assign mpm_phase = (state_q == StMpm);
  // After reset the force sums are cleared once (a reset in the middle of a step would
  // otherwise leave partial sums behind); from then on every MPM pass clears what it read.
  logic clearing_sums;
  assign clearing_sums = (state_q == StClearSums);
  logic [PAW-1:0] clear_addr;
  assign clear_addr = clearing_sums ? PAW'(row_q) : walk1_q;

`ifndef SYNTHESIS
  // Stream protocol and FSM invariants (rtl/rheo_stream_checker.sv): asserted in every
  // verilated core (--assert) and proved by the formal flow; synthesis leaves them out.
  rheo_stream_checker #(
    .W(W), .StateW($bits(state_q)), .NumStates(32'(StForceOut) + 1), .Lanes(Lanes), .BW(BW),
    .DrainW(DrainW), .MaxDrain((TemDrain > MpmDrain ? TemDrain : MpmDrain) - 1),
    .DivStepW(5), .DivSteps(IdxCountW)
  ) u_checker (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast),
    .busy_i(busy_o), .state_i(state_q),
    .holds_word_i(state_q == StRSend || state_q == StStatSend || state_q == StForceOut),
    .bank_i(bank_q), .div_rem_i(div_rem_q), .drain_i(drain_q), .div_step_i(div_step_q));
`endif

  // ---------------------------------------------------------------- lane signals
  // Edge pass, stage 1 (slot record read) and stage 2 (particles read, TEM input).
  logic ev1_q;
  logic [EAW-1:0] row1_q;
  logic [RecW-1:0] rec1 [Lanes];
  logic valid1 [Lanes];
  logic [PAW-1:0] s_local1 [Lanes], e_local1 [Lanes];
  logic [EBW-1:0] e_bank1 [Lanes];
  logic [W-1:0] len1 [Lanes], d1 [Lanes], m1 [Lanes];
  logic [MIdxW-1:0] mat1 [Lanes];
  logic ev2_q [Lanes];
  logic [TemIdxW-1:0] idx2_q [Lanes];
  logic [W-1:0] len2_q [Lanes], d2_q [Lanes], m2_q [Lanes];
  logic [BW-1:0] eb2_q [Lanes];
  logic [6*CoefW-1:0] coef2_q [Lanes];
  logic [2*CoefW-1:0] coef_arm2 [Lanes];
  logic [1:0] mflags2_q [Lanes];
  logic [NumCoef*CoefW-1:0] tem_coef [Lanes];
  logic [3*W-1:0] xs2 [Lanes], xe2 [Lanes], ps2 [Lanes], pe2 [Lanes];
  logic schedule_conflict;
  // TEM outputs.
  logic tem_valid [Lanes], tem_sat [Lanes], tem_deg [Lanes];
  logic [TemIdxW-1:0] tem_idx [Lanes];
  logic [3*W-1:0] tem_f [Lanes];
  logic [W-1:0] tem_d [Lanes], tem_m [Lanes];
  logic [EAW-1:0] tem_row [Lanes];
  logic [PAW-1:0] tem_s_local [Lanes], tem_e_local [Lanes];
  logic [BW-1:0] tem_e_bank [Lanes];
  // Particle banks: memory ports.
  logic [PAW-1:0] xp_a_addr [Lanes], xp_b_addr [Lanes];
  // Words side by side in one vector ({p, x} = 6 words): Yosys 0.23 mis-connects instance
  // ports to elements of two-dimensional unpacked arrays.
  logic [6*W-1:0] xp_a_data [Lanes], xp_b_data [Lanes], xp_b_wdata [Lanes];
  logic [5:0] xp_b_we [Lanes];
  logic [PAW-1:0] xbar_addr [Lanes];
  // Accumulator additions per bank: start side from the own lane, end side via crossbar.
  logic acc_s_valid [Lanes], acc_e_valid [Lanes];
  logic [PAW-1:0] acc_s_addr [Lanes], acc_e_addr [Lanes];
  logic [3*AccW-1:0] acc_s_val [Lanes], acc_e_val [Lanes];
  logic [3*AccW-1:0] sum_s [Lanes], sum_e [Lanes];
  // MPM pass: stage 1 (memories read, sums added), stage 2 (sums saturated) and stage 3
  // (MPM input).
  logic mv1_q [Lanes], mreq2_q [Lanes], mreq3_q [Lanes];
  // A force sum of MPM stage 2 saturated (registered: off the status register's path; the
  // MPM drain leaves it clocks to land before the step ends).
  logic mclip3_q [Lanes];
  logic [PAW-1:0] walk1_q;
  logic [PAW-1:0] midx2_q [Lanes], midx3_q [Lanes];
  logic [3*W-1:0] x0_data [Lanes];
  logic [CoefW-1:0] minv_data [Lanes];
  logic [1:0] pflags_data [Lanes];
  logic [3*SumW-1:0] total1 [Lanes], mtotal2_q [Lanes];
  logic [3*W-1:0] f2 [Lanes];
  logic clip2 [Lanes];
  logic [3*W-1:0] mx2_q [Lanes], mp2_q [Lanes], mx02_q [Lanes];
  logic [3*W-1:0] mf3_q [Lanes], mx3_q [Lanes], mp3_q [Lanes], mx03_q [Lanes];
  logic [CoefW-1:0] mminv2_q [Lanes], mminv3_q [Lanes];
  logic [1:0] mflags2m_q [Lanes], mflags3m_q [Lanes];
  logic mpm_valid [Lanes], mpm_sat [Lanes];
  logic [PAW-1:0] mpm_idx [Lanes];
  logic [3*W-1:0] mpm_x [Lanes], mpm_p [Lanes];
  logic [W-1:0] mpm_plate_f [Lanes];
  // Edge slot memories of each lane (read port data).
  logic [W-1:0] d_a_data [Lanes], m_a_data [Lanes];

  logic [3*W-1:0] gravity_flat;
  assign gravity_flat = {gravity_q[2], gravity_q[1], gravity_q[0]};

  // ---------------------------------------------------------------- lanes
  for (genvar j = 0; j < Lanes; j++) begin : g_lane
    // ---- edge slot memories ----
    logic [EAW-1:0] e_a_addr, e_b_addr;
    logic e_host_we;
    assign e_a_addr = (state_q == StTem) ? EAW'(row_q) : EAW'(local_q);
    assign e_b_addr = tem_valid[j] ? tem_row[j] : EAW'(local_q);
    assign e_host_we = host_we && bank_q == BW'(j) && host_edge_ok;
    logic rec_we, len_we, d_we, mat_we;
    assign rec_we = e_host_we && region_q == 4'(rheo_consts_pkg::RegionEdge) && field_q == 3'd0;
    assign len_we = e_host_we && region_q == 4'(rheo_consts_pkg::RegionEdge) && field_q == 3'd1;
    assign d_we = tem_valid[j] || (e_host_we &&
        ((region_q == 4'(rheo_consts_pkg::RegionEdge) && field_q == 3'd2) ||
         region_q == 4'(rheo_consts_pkg::RegionEdgeLength)));
    assign mat_we = e_host_we && region_q == 4'(rheo_consts_pkg::RegionEdge) && field_q == 3'd3;
    logic [RecW-1:0] rec_wdata;
    assign rec_wdata = {s_axis_tdata[rheo_consts_pkg::EdgeValidBit],
                        s_axis_tdata[rheo_consts_pkg::EdgeEndBankShift +: EBW],
                        s_axis_tdata[rheo_consts_pkg::EdgeEndLocalShift +: PAW],
                        s_axis_tdata[PAW-1:0]};
    rheo_ram_sdp #(.Width(RecW), .Depth(EDepth)) u_rec (
      .clk_i(clk_i), .a_addr_i(e_a_addr), .a_data_o(rec1[j]),
      .b_we_i(rec_we), .b_addr_i(EAW'(local_q)), .b_data_i(rec_wdata));
    rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_len (
      .clk_i(clk_i), .a_addr_i(e_a_addr), .a_data_o(len1[j]),
      .b_we_i(len_we), .b_addr_i(EAW'(local_q)), .b_data_i(s_axis_tdata));
    rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_d (
      .clk_i(clk_i), .a_addr_i(e_a_addr), .a_data_o(d_a_data[j]),
      .b_we_i(d_we), .b_addr_i(e_b_addr), .b_data_i(tem_valid[j] ? tem_d[j] : s_axis_tdata));
    rheo_ram_sdp #(.Width(MIdxW), .Depth(EDepth)) u_mat (
      .clk_i(clk_i), .a_addr_i(e_a_addr), .a_data_o(mat1[j]),
      .b_we_i(mat_we), .b_addr_i(EAW'(local_q)), .b_data_i(s_axis_tdata[MIdxW-1:0]));
    assign d1[j] = d_a_data[j];
    if (MaxwellArm != 0) begin : g_arm
      logic m_we;
      assign m_we = tem_valid[j] ||
          (e_host_we && region_q == 4'(rheo_consts_pkg::RegionEdgeArm));
      rheo_ram_sdp #(.Width(W), .Depth(EDepth)) u_m (
        .clk_i(clk_i), .a_addr_i(e_a_addr), .a_data_o(m_a_data[j]),
        .b_we_i(m_we), .b_addr_i(e_b_addr), .b_data_i(tem_valid[j] ? tem_m[j] : s_axis_tdata));
      assign m1[j] = m_a_data[j];
      assign tem_coef[j] = {coef_arm2[j], coef2_q[j]};
    end else begin : g_no_arm
      assign m_a_data[j] = '0;
      assign m1[j] = '0;
      assign tem_coef[j] = coef2_q[j];
    end

    // ---- edge pass stage 1: the slot's particles ----
    assign valid1[j] = ev1_q && rec1[j][RecW-1];
    assign e_bank1[j] = rec1[j][2*PAW +: EBW];
    assign e_local1[j] = rec1[j][PAW +: PAW];
    assign s_local1[j] = rec1[j][PAW-1:0];

    // ---- edge pass stage 2: TEM inputs (start from the own bank, end via the crossbar) ----
    assign xs2[j] = xp_a_data[j][0 +: 3*W];
    assign ps2[j] = xp_a_data[j][3*W +: 3*W];
    assign xe2[j] = xp_b_data[eb2_q[j]][0 +: 3*W];
    assign pe2[j] = xp_b_data[eb2_q[j]][3*W +: 3*W];

    rheo_tem #(.W(W), .CoefW(CoefW), .IdxW(TemIdxW), .MaxwellArm(MaxwellArm)) u_tem (
      .clk_i       (clk_i),
      .rst_ni      (rst_ni),
      .valid_i     (ev2_q[j]),
      .idx_i       (idx2_q[j]),
      .xs_i        (xs2[j]),
      .xe_i        (xe2[j]),
      .ps_i        (ps2[j]),
      .pe_i        (pe2[j]),
      .d_i         (d2_q[j]),
      .len_i       (len2_q[j]),
      .m_i         (m2_q[j]),
      .coef_i      (tem_coef[j]),
      .mat_flags_i (mflags2_q[j]),
      .valid_o     (tem_valid[j]),
      .idx_o       (tem_idx[j]),
      .f_o         (tem_f[j]),
      .d_o         (tem_d[j]),
      .m_o         (tem_m[j]),
      .sat_o       (tem_sat[j]),
      .degenerate_o(tem_deg[j])
    );
    assign {tem_row[j], tem_s_local[j], tem_e_bank[j], tem_e_local[j]} = tem_idx[j];

    // ---- particle bank j: x and p (6 words), static words, force sums ----
    logic p_host_we;
    assign p_host_we = host_we && bank_q == BW'(j) && host_particle_ok;
    assign xp_a_addr[j] = mpm_phase ? PAW'(row_q) : edge_phase ? s_local1[j] : PAW'(local_q);
    assign xp_b_addr[j] = mpm_valid[j] ? mpm_idx[j] :
                          (state_q == StWData) ? PAW'(local_q) : xbar_addr[j];
    for (genvar w = 0; w < 6; w++) begin : g_xp
      assign xp_b_we[j][w] = mpm_valid[j] || (p_host_we && field_q == 3'(w) &&
          region_q == 4'(rheo_consts_pkg::RegionParticleState));
      if (w < 3) begin : g_x
        assign xp_b_wdata[j][w*W +: W] = mpm_valid[j] ? mpm_x[j][w*W +: W] : s_axis_tdata;
      end else begin : g_p
        assign xp_b_wdata[j][w*W +: W] = mpm_valid[j] ? mpm_p[j][(w-3)*W +: W] : s_axis_tdata;
      end
      rheo_ram_tdp #(.Width(W), .Depth(PDepth)) u_xp (
        .clk_i(clk_i), .a_addr_i(xp_a_addr[j]), .a_data_o(xp_a_data[j][w*W +: W]),
        .b_we_i(xp_b_we[j][w]), .b_addr_i(xp_b_addr[j]), .b_data_i(xp_b_wdata[j][w*W +: W]),
        .b_data_o(xp_b_data[j][w*W +: W]));
    end
    logic static_we;
    assign static_we = p_host_we && region_q == 4'(rheo_consts_pkg::RegionParticleStatic);
    for (genvar w = 0; w < 3; w++) begin : g_x0
      rheo_ram_sdp #(.Width(W), .Depth(PDepth)) u_x0 (
        .clk_i(clk_i), .a_addr_i(PAW'(row_q)), .a_data_o(x0_data[j][w*W +: W]),
        .b_we_i(static_we && field_q == 3'(w)), .b_addr_i(PAW'(local_q)),
        .b_data_i(s_axis_tdata));
    end
    rheo_ram_sdp #(.Width(CoefW), .Depth(PDepth)) u_minv (
      .clk_i(clk_i), .a_addr_i(PAW'(row_q)), .a_data_o(minv_data[j]),
      .b_we_i(static_we && field_q == 3'd3), .b_addr_i(PAW'(local_q)),
      .b_data_i(s_axis_tdata[CoefW-1:0]));
    rheo_ram_sdp #(.Width(2), .Depth(PDepth)) u_pflags (
      .clk_i(clk_i), .a_addr_i(PAW'(row_q)), .a_data_o(pflags_data[j]),
      .b_we_i(static_we && field_q == 3'd4), .b_addr_i(PAW'(local_q)),
      .b_data_i(s_axis_tdata[1:0]));
    rheo_force_acc #(.AccW(AccW), .Depth(PDepth)) u_sum_start (
      .clk_i(clk_i), .rst_ni(rst_ni),
      .add_valid_i(acc_s_valid[j]), .add_addr_i(acc_s_addr[j]), .add_val_i(acc_s_val[j]),
      .sum_addr_i(PAW'(row_q)), .sum_o(sum_s[j]),
      .clear_i(mv1_q[j] || clearing_sums), .clear_addr_i(clear_addr));
    rheo_force_acc #(.AccW(AccW), .Depth(PDepth)) u_sum_end (
      .clk_i(clk_i), .rst_ni(rst_ni),
      .add_valid_i(acc_e_valid[j]), .add_addr_i(acc_e_addr[j]), .add_val_i(acc_e_val[j]),
      .sum_addr_i(PAW'(row_q)), .sum_o(sum_e[j]),
      .clear_i(mv1_q[j] || clearing_sums), .clear_addr_i(clear_addr));

    // ---- MPM pass stage 1: start sum + end sum; stage 2: saturated once ----
    // (two clocks, so that the 41-bit addition and the saturation compare are not in a row)
    always_comb begin
      for (int i = 0; i < 3; i++)
        total1[j][i*SumW +: SumW] = SumW'($signed(sum_s[j][i*AccW +: AccW])) +
                                    SumW'($signed(sum_e[j][i*AccW +: AccW]));
    end
    // Saturation to W bits (rheo_consts_pkg::sat_word): a sum fits iff its bits SumW-1..W-1
    // are all equal, an AND/OR tree beside the word rather than two comparator chains.
    always_comb begin
      clip2[j] = 1'b0;
      for (int i = 0; i < 3; i++) begin
        logic [SumW-W:0] hi;
        logic fits, sign;
        hi = mtotal2_q[j][i*SumW + W-1 +: SumW-W+1];
        sign = mtotal2_q[j][i*SumW + SumW-1];
        fits = (&hi) | ~(|hi);
        f2[j][i*W +: W] = fits ? mtotal2_q[j][i*SumW +: W] : {sign, {(W-1){~sign}}};
        clip2[j] = clip2[j] | ~fits;
      end
    end

    rheo_mpm #(.W(W), .CoefW(CoefW), .IdxW(PAW)) u_mpm (
      .clk_i     (clk_i),
      .rst_ni    (rst_ni),
      .valid_i   (mreq3_q[j]),
      .idx_i     (midx3_q[j]),
      .f_i       (mf3_q[j]),
      .x_i       (mx3_q[j]),
      .p_i       (mp3_q[j]),
      .x0_i      (mx03_q[j]),
      .minv_i    (mminv3_q[j]),
      .flags_i   (mflags3m_q[j]),
      .g_i       (gravity_flat),
      .plate_z_i (plate_z_q),
      .plate_en_i(plate_en_q),
      .floor_en_i(floor_en_q),
      .hold_en_i (plate_hold_en_q & plate_prev_valid_q),
      .plate_prev_i(plate_prev_q),
      .valid_o   (mpm_valid[j]),
      .idx_o     (mpm_idx[j]),
      .x_o       (mpm_x[j]),
      .p_o       (mpm_p[j]),
      .plate_f_o (mpm_plate_f[j]),
      .sat_o     (mpm_sat[j])
    );
  end

  // ---------------------------------------------------------------- crossbars
  // Stage 1: bank b's port B reads the end particle of the lane whose end lies in bank b.
  // Two ends in one bank (or an end bank beyond the lanes) is a schedule conflict.
  always_comb begin
    schedule_conflict = 1'b0;
    for (int b = 0; b < Lanes; b++) begin
      xbar_addr[b] = '0;
      for (int j = Lanes - 1; j >= 0; j--) begin
        if (valid1[j] && e_bank1[j] == EBW'(b)) xbar_addr[b] = e_local1[j];
      end
    end
    for (int j = 0; j < Lanes; j++) begin
      if (valid1[j] && e_bank1[j] >= EBW'(Lanes)) schedule_conflict = 1'b1;
      for (int k = j + 1; k < Lanes; k++) begin
        if (valid1[j] && valid1[k] && e_bank1[j] == e_bank1[k]) schedule_conflict = 1'b1;
      end
    end
  end

  // TEM results: +F to the start sum of the own bank, -F to the end sum of the end's bank.
  always_comb begin
    for (int b = 0; b < Lanes; b++) begin
      acc_s_valid[b] = tem_valid[b];
      acc_s_addr[b] = tem_s_local[b];
      acc_e_valid[b] = 1'b0;
      acc_e_addr[b] = '0;
      for (int i = 0; i < 3; i++) begin
        acc_s_val[b][i*AccW +: AccW] = AccW'($signed(tem_f[b][i*W +: W]));
        acc_e_val[b][i*AccW +: AccW] = '0;
      end
      for (int j = Lanes - 1; j >= 0; j--) begin
        if (tem_valid[j] && tem_e_bank[j] == BW'(b)) begin
          acc_e_valid[b] = 1'b1;
          acc_e_addr[b] = tem_e_local[j];
          for (int i = 0; i < 3; i++)
            acc_e_val[b][i*AccW +: AccW] = -(AccW'($signed(tem_f[j][i*W +: W])));
        end
      end
    end
  end

  // Plate force of this cycle from all lanes. It is registered (plate_in_q) before it is
  // added to the wide accumulator, and the accumulator is narrowed to a word one clock
  // after its last addition, so that no clock holds the lane sum, the 48-bit addition and
  // the saturation compare in a row (MpmDrain counts these two clocks).
  localparam int PlateInW = W + $clog2(Lanes + 1);
  logic signed [PlateInW-1:0] plate_in, plate_in_q;
  always_comb begin
    plate_in = '0;
    for (int j = 0; j < Lanes; j++) begin
      if (mpm_valid[j]) plate_in = plate_in + PlateInW'($signed(mpm_plate_f[j]));
    end
  end

  // No asynchronous reset: the accumulator is cleared when a step's plate word arrives, so
  // the clear maps to the flip-flops' synchronous reset instead of a LUT behind the carry
  // chain.
  always_ff @(posedge clk_i) begin
    plate_in_q <= plate_in;
    if (state_q == StRunPlate && in_fire) plate_acc_q <= '0;
    else plate_acc_q <= plate_acc_q + PlateAccW'(plate_in_q);
  end

  // ---------------------------------------------------------------- pipeline registers
  always_ff @(posedge clk_i) begin
    row1_q <= EAW'(row_q);
    walk1_q <= PAW'(row_q);
    for (int j = 0; j < Lanes; j++) begin
      // Edge pass stage 1 -> 2.
      idx2_q[j] <= {row1_q, s_local1[j], BW'(e_bank1[j]), e_local1[j]};
      eb2_q[j] <= BW'(e_bank1[j]);
      len2_q[j] <= len1[j];
      d2_q[j] <= d1[j];
      m2_q[j] <= m1[j];
      coef2_q[j] <= {mat_coef[mat1[j]][5], mat_coef[mat1[j]][4], mat_coef[mat1[j]][3],
                     mat_coef[mat1[j]][2], mat_coef[mat1[j]][1], mat_coef[mat1[j]][0]};
      mflags2_q[j] <= mat_flags[mat1[j]];
      // MPM pass stage 1 -> 2.
      midx2_q[j] <= walk1_q;
      mtotal2_q[j] <= total1[j];
      mx2_q[j] <= xp_a_data[j][0 +: 3*W];
      mp2_q[j] <= xp_a_data[j][3*W +: 3*W];
      mx02_q[j] <= x0_data[j];
      mminv2_q[j] <= minv_data[j];
      mflags2m_q[j] <= pflags_data[j];
      // MPM pass stage 2 -> 3.
      midx3_q[j] <= midx2_q[j];
      mf3_q[j] <= f2[j];
      mx3_q[j] <= mx2_q[j];
      mp3_q[j] <= mp2_q[j];
      mx03_q[j] <= mx02_q[j];
      mminv3_q[j] <= mminv2_q[j];
      mflags3m_q[j] <= mflags2m_q[j];
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      ev1_q <= 1'b0;
      for (int j = 0; j < Lanes; j++) begin
        ev2_q[j] <= 1'b0;
        mv1_q[j] <= 1'b0;
        mreq2_q[j] <= 1'b0;
        mreq3_q[j] <= 1'b0;
        mclip3_q[j] <= 1'b0;
      end
    end else begin
      ev1_q <= (state_q == StTem) && (row_q < edge_rows_q);
      for (int j = 0; j < Lanes; j++) begin
        ev2_q[j] <= valid1[j];
        mv1_q[j] <= mpm_phase && (base_q + IdxCountW'(j) < num_particles_q);
        mreq2_q[j] <= mv1_q[j];
        mreq3_q[j] <= mreq2_q[j];
        mclip3_q[j] <= mreq2_q[j] && clip2[j];
      end
    end
  end

  // ---------------------------------------------------------------- material tables
  always_ff @(posedge clk_i) begin
    // Host writes only while idle.
    if (host_we && region_q == 4'(rheo_consts_pkg::RegionMaterial) &&
        index_q < IdxCountW'(MaxMaterials)) begin
      if (field_q < 6) mat_coef[MIdxW'(index_q)][field_q] <= s_axis_tdata[CoefW-1:0];
      else mat_flags[MIdxW'(index_q)] <= s_axis_tdata[1:0];
    end
  end

  if (MaxwellArm != 0) begin : g_arm_mat
    logic [CoefW-1:0] mat_arm [MaxMaterials][2];
    always_ff @(posedge clk_i) begin
      if (host_we && region_q == 4'(rheo_consts_pkg::RegionMaterialArm) &&
          index_q < IdxCountW'(MaxMaterials))
        mat_arm[MIdxW'(index_q)][field_q[0]] <= s_axis_tdata[CoefW-1:0];
      for (int j = 0; j < Lanes; j++) coef_arm2[j] <= {mat_arm[mat1[j]][1], mat_arm[mat1[j]][0]};
    end
  end else begin : g_no_arm_mat
    logic unused_arm;
    always_comb begin
      unused_arm = 1'b0;
      for (int j = 0; j < Lanes; j++) begin
        coef_arm2[j] = '0;
        unused_arm = unused_arm ^ (^tem_m[j]) ^ (^coef_arm2[j]) ^ (^m_a_data[j]);
      end
    end
  end

  // ---------------------------------------------------------------- read-back mux
  // The memories' read port A follows (bank_q, local_q) while idle; StRFetch waits for
  // the registered read, StRLoad takes the word. The word's source is decoded from
  // (region, bank, field) into one-hot selects registered in StRFetch (they do not change
  // until StRSend), so in StRLoad the block-RAM outputs meet only an AND-OR.
  logic [5:0] sel_xp_q [Lanes];
  logic sel_d_q [Lanes], sel_m_q [Lanes];
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      for (int f = 0; f < 6; f++) begin
        sel_xp_q[j][f] <= region_q == 4'(rheo_consts_pkg::RegionParticleState) &&
                          host_particle_ok && bank_q == BW'(j) && field_q == 3'(f);
      end
      sel_d_q[j] <= region_q == 4'(rheo_consts_pkg::RegionEdgeLength) && host_edge_ok &&
                    bank_q == BW'(j);
      sel_m_q[j] <= MaxwellArm != 0 && region_q == 4'(rheo_consts_pkg::RegionEdgeArm) &&
                    host_edge_ok && bank_q == BW'(j);
    end
  end
  logic [W-1:0] read_word;
  always_comb begin
    read_word = '0;
    for (int j = 0; j < Lanes; j++) begin
      for (int f = 0; f < 6; f++) begin
        if (sel_xp_q[j][f]) read_word = read_word | xp_a_data[j][f*W +: W];
      end
      if (sel_d_q[j]) read_word = read_word | d_a_data[j];
      if (sel_m_q[j]) read_word = read_word | m_a_data[j];
    end
  end

  logic [W-1:0] status_word;
  always_comb begin
    case (field_q)
      3'd0: status_word = status_q;
      3'd1: status_word = step_count_q;
      3'd2: status_word = cycle_count_q;
      default: status_word = 32'(Lanes);
    endcase
  end

  // ---------------------------------------------------------------- control FSM
  logic [31:0] lane_flags;
  always_comb begin
    lane_flags = '0;
    if (schedule_conflict) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusScheduleConflict);
    for (int j = 0; j < Lanes; j++) begin
      if (tem_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusTemSat);
      if (tem_deg[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusDegenerate);
      if (mpm_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
      if (mclip3_q[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
    end
  end

  // Bank and local address of entry index_q + 1 (particle index_q + 1 or edge slot
  // index_q + 1), taken by WRITE and READ commands when an entry is done.
  logic [BW-1:0] next_bank;
  logic [IdxCountW-1:0] next_local;
  always_comb begin
    if (bank_q == BW'(Lanes - 1)) begin
      next_bank = '0;
      next_local = local_q + 24'd1;
    end else begin
      next_bank = bank_q + BW'(1);
      next_local = local_q;
    end
  end

  // Shift-subtract division of the command's start index by Lanes, one bit per clock.
  localparam int TrialW = BW + 1;
  logic [TrialW-1:0] div_trial;
  logic [BW-1:0] div_rem_next;
  logic div_take;
  assign div_trial = {div_rem_q, div_num_q[IdxCountW-1]};
  assign div_take = div_trial >= TrialW'(Lanes);
  assign div_rem_next = BW'(div_take ? div_trial - TrialW'(Lanes) : div_trial);

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= StClearSums;
      reading_q <= 1'b0;
      region_q <= '0;
      last_field_q <= rheo_consts_pkg::words_per_entry(4'd0) - 3'd1;
      count_q <= '0;
      index_q <= '0;
      local_q <= '0;
      bank_q <= '0;
      div_num_q <= '0;
      div_rem_q <= '0;
      div_step_q <= '0;
      field_q <= '0;
      clear_q <= 1'b0;
      row_q <= '0;
      base_q <= '0;
      drain_q <= '0;
      out_data_q <= '0;
      out_valid_q <= 1'b0;
      out_last_q <= 1'b0;
      num_particles_q <= '0;
      edge_rows_q <= '0;
      for (int i = 0; i < 3; i++) gravity_q[i] <= '0;
      floor_en_q <= 1'b0;
      plate_en_q <= 1'b0;
      plate_z_q <= '0;
      plate_hold_en_q <= 1'b0;
      plate_prev_valid_q <= 1'b0;
      plate_prev_q <= '0;
      status_q <= '0;
      step_count_q <= '0;
      cycle_count_q <= '0;
    end else begin
      status_q <= status_q | lane_flags;
      if (busy_o) cycle_count_q <= cycle_count_q + 32'd1;
      case (state_q)
        StClearSums: begin
          if (row_q == IdxCountW'(PDepth - 1)) begin
            row_q <= '0;
            state_q <= StIdle;
          end else begin
            row_q <= row_q + 24'd1;
          end
        end
        StIdle: begin
          if (in_fire) begin
            region_q <= s_axis_tdata[27:24];
            last_field_q <= rheo_consts_pkg::words_per_entry(s_axis_tdata[27:24]) - 3'd1;
            count_q <= s_axis_tdata[23:0];
            field_q <= '0;
            case (s_axis_tdata[31:28])
              4'(rheo_consts_pkg::OpWrite), 4'(rheo_consts_pkg::OpRead): begin
                reading_q <= s_axis_tdata[31:28] == 4'(rheo_consts_pkg::OpRead);
                if (s_axis_tdata[27:24] >= 4'(CoreRegions))
                  status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                else if (s_axis_tdata[31:28] == 4'(rheo_consts_pkg::OpRead))
                  state_q <= StRStart;
                else state_q <= StWStart;
              end
              4'(rheo_consts_pkg::OpRun): begin
                if (s_axis_tdata[23:0] != 0) state_q <= StRunPlate;
              end
              4'(rheo_consts_pkg::OpStatus): begin
                clear_q <= s_axis_tdata[0];
                state_q <= StStatFetch;
              end
              default: status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
            endcase
          end
        end
        StWStart, StRStart: begin
          if (in_fire) begin
            index_q <= s_axis_tdata[23:0];
            div_num_q <= s_axis_tdata[23:0];
            div_rem_q <= '0;
            div_step_q <= '0;
            local_q <= '0;
            state_q <= (count_q == 0) ? StIdle : StDivide;
          end
        end
        StDivide: begin
          div_num_q <= div_num_q << 1;
          div_rem_q <= div_rem_next;
          local_q <= {local_q[IdxCountW-2:0], div_take};
          div_step_q <= div_step_q + 5'd1;
          if (div_step_q == 5'(IdxCountW - 1)) begin
            bank_q <= div_rem_next;
            state_q <= reading_q ? StRFetch : StWData;
          end
        end
        StWData: begin
          if (in_fire) begin
            if (region_q == 4'(rheo_consts_pkg::RegionGlobals)) begin
              case (index_q)
                // Counts beyond the memories would wrap the addresses: refused.
                IdxCountW'(rheo_consts_pkg::GlobalNumParticles): begin
                  if (s_axis_tdata[23:0] > IdxCountW'(MaxParticles))
                    status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                  else num_particles_q <= s_axis_tdata[23:0];
                end
                IdxCountW'(rheo_consts_pkg::GlobalEdgeRows): begin
                  if (s_axis_tdata[23:0] > IdxCountW'(EDepth))
                    status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                  else edge_rows_q <= s_axis_tdata[23:0];
                end
                IdxCountW'(rheo_consts_pkg::GlobalGravityX): gravity_q[0] <= s_axis_tdata;
                IdxCountW'(rheo_consts_pkg::GlobalGravityY): gravity_q[1] <= s_axis_tdata;
                IdxCountW'(rheo_consts_pkg::GlobalGravityZ): gravity_q[2] <= s_axis_tdata;
                IdxCountW'(rheo_consts_pkg::GlobalControl): begin
                  floor_en_q <= s_axis_tdata[rheo_consts_pkg::ControlFloorBit];
                  plate_en_q <= s_axis_tdata[rheo_consts_pkg::ControlPlateBit];
                  plate_hold_en_q <= s_axis_tdata[rheo_consts_pkg::ControlPlateHoldBit];
                  plate_prev_valid_q <= 1'b0;
                end
                default: status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
              endcase
            end
            if (entry_done) begin
              field_q <= '0;
              index_q <= index_q + 24'd1;
              bank_q <= next_bank;
              local_q <= next_local;
              count_q <= count_q - 24'd1;
              if (count_q == 24'd1) state_q <= StIdle;
            end else begin
              field_q <= field_q + 3'd1;
            end
          end
        end
        StRFetch: state_q <= StRLoad;
        StRLoad: begin
          out_data_q <= read_word;
          out_valid_q <= 1'b1;
          out_last_q <= (count_q == 24'd1) && entry_done;
          state_q <= StRSend;
        end
        StRSend: begin
          if (out_fire) begin
            out_valid_q <= 1'b0;
            out_last_q <= 1'b0;
            if (entry_done) begin
              field_q <= '0;
              index_q <= index_q + 24'd1;
              bank_q <= next_bank;
              local_q <= next_local;
              count_q <= count_q - 24'd1;
              state_q <= (count_q == 24'd1) ? StIdle : StRFetch;
            end else begin
              field_q <= field_q + 3'd1;
              state_q <= StRFetch;
            end
          end
        end
        StStatFetch: begin
          out_data_q <= status_word;
          out_valid_q <= 1'b1;
          out_last_q <= (field_q == 3'(rheo_consts_pkg::StatusWords - 1));
          state_q <= StStatSend;
        end
        StStatSend: begin
          if (out_fire) begin
            out_valid_q <= 1'b0;
            out_last_q <= 1'b0;
            if (field_q == 3'(rheo_consts_pkg::StatusWords - 1)) begin
              field_q <= '0;
              if (clear_q) status_q <= lane_flags;
              state_q <= StIdle;
            end else begin
              field_q <= field_q + 3'd1;
              state_q <= StStatFetch;
            end
          end
        end
        StRunPlate: begin
          if (in_fire) begin
            plate_z_q <= s_axis_tdata;
            plate_prev_q <= plate_z_q;
            plate_prev_valid_q <= 1'b1;
            row_q <= '0;
            state_q <= StTem;
          end
        end
        StTem: begin
          if (row_q + 24'd1 >= edge_rows_q) begin
            row_q <= '0;
            drain_q <= DrainW'(TemDrain - 1);
            state_q <= StTemDrain;
          end else begin
            row_q <= row_q + 24'd1;
          end
        end
        StTemDrain: begin
          base_q <= '0;
          if (drain_q == 0) state_q <= StMpm;
          else drain_q <= drain_q - 1'b1;
        end
        StMpm: begin
          if (base_q + 24'(Lanes) >= num_particles_q) begin
            row_q <= '0;
            drain_q <= DrainW'(MpmDrain - 1);
            state_q <= StMpmDrain;
          end else begin
            row_q <= row_q + 24'd1;
            base_q <= base_q + 24'(Lanes);
          end
        end
        StMpmDrain: begin
          if (drain_q == 0) begin
            out_data_q <= rheo_consts_pkg::sat_word(WideW'(plate_acc_q));
            if (rheo_consts_pkg::clips(WideW'(plate_acc_q), W))
              status_q <= status_q | lane_flags | 32'(rheo_consts_pkg::StatusPlateSat);
            out_valid_q <= 1'b1;
            out_last_q <= (count_q == 24'd1);
            step_count_q <= step_count_q + 32'd1;
            state_q <= StForceOut;
          end else begin
            drain_q <= drain_q - 1'b1;
          end
        end
        StForceOut: begin
          if (out_fire) begin
            out_valid_q <= 1'b0;
            out_last_q <= 1'b0;
            count_q <= count_q - 24'd1;
            state_q <= (count_q == 24'd1) ? StIdle : StRunPlate;
          end
        end
        default: state_q <= StIdle;
      endcase
    end
  end
endmodule
