// Rheological-object core: particle and edge state in on-chip memories, Lanes parallel
// TEM and MPM lanes, and an AXI4-Stream style command interface (format in
// host/driver/frame_format.hpp, constants in rheo_consts_pkg).
//
// One step (after the plate-height word arrives):
//   TEM pass: row t = 0 .. ceil(E/Lanes)-1, lane j evaluates edge t*Lanes + j and writes
//             its force vector to the edge-force memory and its new Voigt length back.
//   drain:    TemDrain clocks until the last force is written.
//   MPM pass: row t = 0 .. G-1 of the host-built gather table, lane j reads entry
//             t*Lanes + j: adds +-F of one incident edge to its accumulator; on a
//             particle's last entry the sum goes through the lane's MPM, which writes x
//             and p back and adds its plate force (no read-modify-write hazards: each edge
//             force is written once before it is read, each particle updated once).
//   drain:    MpmDrain clocks until the last particle is written; then the plate-force
//             word is sent.
// Compute clocks per step (counted in status word 2):
//   ceil(E / Lanes) + TemDrain + G + MpmDrain,   G = max over lanes of
//   sum over the lane's particles of max(degree, 1)   (host: gather_rows()).
// MaxwellArm = 1 builds the variant with the parallel Maxwell arm in every TEM: per edge
// the arm's extension m (region EdgeArm, read and written like d) and per material
// gamma and k2t (region MaterialArm). Same cycles per step. MaxwellArm = 0 is the baseline
// core (the arm regions are refused as bad commands).
// Memories: every array has one write port per lane and synchronous reads; the particle
// arrays are read by 2 TEM ports + 1 MPM port per lane (replicated RAMB16 in a
// synthesis for Virtex-II, see docs/hardware.md).
module rheo_core #(
  parameter int Lanes = 1,              // parallel TEM/MPM lanes (1..4)
  parameter int MaxParticles = 4096,    // particle memory depth
  parameter int MaxEdges = 65536,       // edge memory depth
  parameter int MaxGather = 139264,     // gather table depth (rows * Lanes)
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
  localparam int PIdxW = $clog2(MaxParticles);
  localparam int EIdxW = $clog2(MaxEdges);
  localparam int GIdxW = $clog2(MaxGather);
  localparam int MIdxW = $clog2(MaxMaterials);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int ForceAccW = rheo_consts_pkg::ForceAccW;
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW;
  // Clocks from the last TEM issue until its force is written: edge read, particle read,
  // 18 TEM stages, write. From the last gather issue until the particle is written:
  // gather read, force read, accumulate, particle read, 5 MPM stages, write.
  localparam int TemDrain = rheo_consts_pkg::TemDrain;
  localparam int MpmDrain = rheo_consts_pkg::MpmDrain;
  localparam int NumCoef = (MaxwellArm != 0) ? 8 : 6;
  localparam int CoreRegions =
      (MaxwellArm != 0) ? rheo_consts_pkg::NumRegions : rheo_consts_pkg::NumBaseRegions;

  if (W != rheo_consts_pkg::Width || CoefW != rheo_consts_pkg::CoefW) begin : g_check
    $error("rheo_core: W/CoefW must match rheo_consts_pkg");
  end
  if (Lanes < 1 || Lanes > 4) begin : g_lanes_check
    $error("rheo_core: Lanes must be 1..4");
  end

  // ---------------------------------------------------------------- memories
  logic [W-1:0] px_mem [MaxParticles][3];
  logic [W-1:0] pp_mem [MaxParticles][3];
  logic [W-1:0] x0_mem [MaxParticles][3];
  logic [CoefW-1:0] minv_mem [MaxParticles];
  logic [1:0] pflags_mem [MaxParticles];
  logic [PIdxW-1:0] es_mem [MaxEdges];
  logic [PIdxW-1:0] ee_mem [MaxEdges];
  logic [W-1:0] elen_mem [MaxEdges];
  logic [W-1:0] ed_mem [MaxEdges];
  logic [MIdxW-1:0] emat_mem [MaxEdges];
  logic [W-1:0] ef_mem [MaxEdges][3];
  logic [CoefW-1:0] mat_coef [MaxMaterials][6];
  logic [1:0] mat_flags [MaxMaterials];
  logic [30:0] gather_mem [MaxGather];

  // ---------------------------------------------------------------- registers
  logic [23:0] num_particles_q, num_edges_q, gather_rows_q;
  logic [W-1:0] gravity_q [3];
  logic floor_en_q, plate_en_q;
  logic [W-1:0] plate_z_q;
  logic [31:0] status_q, step_count_q, cycle_count_q;

  typedef enum logic [3:0] {
    StIdle, StWStart, StWData, StRStart, StRFetch, StRSend, StStatFetch, StStatSend,
    StRunPlate, StTem, StTemDrain, StGather, StMpmDrain, StForceOut
  } state_e;
  state_e state_q;
  logic [3:0] region_q;
  logic [23:0] count_q;     // entries (or steps) remaining
  logic [23:0] index_q;     // current entry
  logic [2:0] field_q;      // word within the entry
  logic clear_q;            // status: clear after reading
  logic [23:0] row_q;       // TEM/gather row
  // wide enough for either drain (the TEM's is 43 clocks)
  localparam int DrainW = $clog2((TemDrain > MpmDrain) ? TemDrain : MpmDrain);
  logic [DrainW-1:0] drain_q;
  logic [W-1:0] out_data_q;
  logic out_valid_q, out_last_q;
  logic signed [PlateAccW-1:0] plate_acc_q;

  logic [23:0] tem_rows;
  assign tem_rows = (num_edges_q + 24'(Lanes - 1)) / 24'(Lanes);

  // ---------------------------------------------------------------- stream handshakes
  logic in_fire, out_fire;
  assign s_axis_tready = (state_q == StIdle) || (state_q == StWStart) || (state_q == StWData) ||
                         (state_q == StRStart) || (state_q == StRunPlate);
  assign in_fire = s_axis_tvalid && s_axis_tready;
  assign out_fire = out_valid_q && m_axis_tready;
  assign m_axis_tdata = out_data_q;
  assign m_axis_tvalid = out_valid_q;
  assign m_axis_tlast = out_last_q;
  assign busy_o = (state_q == StTem) || (state_q == StTemDrain) || (state_q == StGather) ||
                  (state_q == StMpmDrain);

  logic [2:0] wpe;
  assign wpe = rheo_consts_pkg::words_per_entry(region_q);
  logic entry_done;
  assign entry_done = (field_q == wpe - 3'd1);

  // ---------------------------------------------------------------- TEM lanes
  logic tem_issue;
  assign tem_issue = (state_q == StTem);
  logic ev1 [Lanes], ev2 [Lanes];
  logic [EIdxW-1:0] eidx1 [Lanes], eidx2 [Lanes];
  logic [PIdxW-1:0] es1 [Lanes], ee1 [Lanes];
  logic [W-1:0] elen1 [Lanes], ed1 [Lanes], elen2 [Lanes], ed2 [Lanes];
  logic [MIdxW-1:0] emat1 [Lanes];
  logic [3*W-1:0] xs2 [Lanes], xe2 [Lanes], ps2 [Lanes], pe2 [Lanes];
  logic [6*CoefW-1:0] coef2 [Lanes];
  logic [1:0] mflags2 [Lanes];
  logic tem_valid [Lanes], tem_sat [Lanes], tem_deg [Lanes];
  logic [EIdxW-1:0] tem_idx [Lanes];
  logic [3*W-1:0] tem_f [Lanes];
  logic [W-1:0] tem_d [Lanes];
  // Maxwell arm lane signals (driven in g_arm_mem; constant 0 without the arm).
  logic [W-1:0] em2 [Lanes], tem_m [Lanes];
  logic [2*CoefW-1:0] coef_arm2 [Lanes];
  logic [NumCoef*CoefW-1:0] tem_coef [Lanes];
  logic [W-1:0] arm_read_word;

  for (genvar j = 0; j < Lanes; j++) begin : g_tem
    if (MaxwellArm != 0) begin : g_coef_arm
      assign tem_coef[j] = {coef_arm2[j], coef2[j]};
    end else begin : g_coef
      assign tem_coef[j] = coef2[j];
    end
    rheo_tem #(.W(W), .CoefW(CoefW), .IdxW(EIdxW), .MaxwellArm(MaxwellArm)) u_tem (
      .clk_i       (clk_i),
      .rst_ni      (rst_ni),
      .valid_i     (ev2[j]),
      .idx_i       (eidx2[j]),
      .xs_i        (xs2[j]),
      .xe_i        (xe2[j]),
      .ps_i        (ps2[j]),
      .pe_i        (pe2[j]),
      .d_i         (ed2[j]),
      .len_i       (elen2[j]),
      .m_i         (em2[j]),
      .coef_i      (tem_coef[j]),
      .mat_flags_i (mflags2[j]),
      .valid_o     (tem_valid[j]),
      .idx_o       (tem_idx[j]),
      .f_o         (tem_f[j]),
      .d_o         (tem_d[j]),
      .m_o         (tem_m[j]),
      .sat_o       (tem_sat[j]),
      .degenerate_o(tem_deg[j])
    );
  end

  // ---------------------------------------------------------------- gather + MPM lanes
  logic gather_issue;
  assign gather_issue = (state_q == StGather);
  logic gv1 [Lanes], gv2 [Lanes];
  logic [30:0] gent1 [Lanes], gent2 [Lanes];
  logic [W-1:0] gf2 [Lanes][3];
  logic signed [ForceAccW-1:0] acc_q [Lanes][3];
  logic mreq3 [Lanes], mreq4 [Lanes];
  logic [PIdxW-1:0] midx3 [Lanes], midx4 [Lanes];
  logic [W-1:0] mf3 [Lanes][3];
  logic [3*W-1:0] mf4 [Lanes], mx4 [Lanes], mp4 [Lanes], mx04 [Lanes];
  logic [CoefW-1:0] mminv4 [Lanes];
  logic [1:0] mflags4 [Lanes];
  logic mpm_valid [Lanes], mpm_sat [Lanes];
  logic [PIdxW-1:0] mpm_idx [Lanes];
  logic [3*W-1:0] mpm_x [Lanes], mpm_p [Lanes];
  logic [W-1:0] mpm_plate_f [Lanes];
  logic [3*W-1:0] gravity_flat;
  assign gravity_flat = {gravity_q[2], gravity_q[1], gravity_q[0]};

  for (genvar j = 0; j < Lanes; j++) begin : g_mpm
    rheo_mpm #(.W(W), .CoefW(CoefW), .IdxW(PIdxW)) u_mpm (
      .clk_i     (clk_i),
      .rst_ni    (rst_ni),
      .valid_i   (mreq4[j]),
      .idx_i     (midx4[j]),
      .f_i       (mf4[j]),
      .x_i       (mx4[j]),
      .p_i       (mp4[j]),
      .x0_i      (mx04[j]),
      .minv_i    (mminv4[j]),
      .flags_i   (mflags4[j]),
      .g_i       (gravity_flat),
      .plate_z_i (plate_z_q),
      .plate_en_i(plate_en_q),
      .floor_en_i(floor_en_q),
      .valid_o   (mpm_valid[j]),
      .idx_o     (mpm_idx[j]),
      .x_o       (mpm_x[j]),
      .p_o       (mpm_p[j]),
      .plate_f_o (mpm_plate_f[j]),
      .sat_o     (mpm_sat[j])
    );
  end

  // Accumulator next values and the saturated particle force sums (gather stage 2).
  logic signed [ForceAccW-1:0] acc_next [Lanes][3];
  logic signed [W-1:0] acc_sat [Lanes][3];
  logic acc_clip [Lanes];
  always_comb begin
    for (int j = 0; j < Lanes; j++) begin
      acc_clip[j] = 1'b0;
      for (int i = 0; i < 3; i++) begin
        acc_next[j][i] = acc_q[j][i];
        if (gv2[j] && gent2[j][28]) begin
          if (gent2[j][29]) acc_next[j][i] = acc_q[j][i] - ForceAccW'($signed(gf2[j][i]));
          else acc_next[j][i] = acc_q[j][i] + ForceAccW'($signed(gf2[j][i]));
        end
        acc_sat[j][i] = rheo_consts_pkg::sat_word(WideW'(acc_next[j][i]));
        acc_clip[j] = acc_clip[j] | rheo_consts_pkg::clips(WideW'(acc_next[j][i]), W);
      end
    end
  end

  // Plate force of this cycle from all lanes.
  logic signed [PlateAccW-1:0] plate_sum;
  always_comb begin
    plate_sum = plate_acc_q;
    for (int j = 0; j < Lanes; j++) begin
      if (mpm_valid[j]) plate_sum = plate_sum + PlateAccW'($signed(mpm_plate_f[j]));
    end
  end

  // ---------------------------------------------------------------- datapath lanes
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      // TEM fetch 1: edge memory
      eidx1[j] <= EIdxW'(row_q * 24'(Lanes) + 24'(j));
      es1[j] <= es_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
      ee1[j] <= ee_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
      elen1[j] <= elen_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
      ed1[j] <= ed_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
      emat1[j] <= emat_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
      // TEM fetch 2: particle memory and material table
      eidx2[j] <= eidx1[j];
      elen2[j] <= elen1[j];
      ed2[j] <= ed1[j];
      xs2[j] <= {px_mem[es1[j]][2], px_mem[es1[j]][1], px_mem[es1[j]][0]};
      xe2[j] <= {px_mem[ee1[j]][2], px_mem[ee1[j]][1], px_mem[ee1[j]][0]};
      ps2[j] <= {pp_mem[es1[j]][2], pp_mem[es1[j]][1], pp_mem[es1[j]][0]};
      pe2[j] <= {pp_mem[ee1[j]][2], pp_mem[ee1[j]][1], pp_mem[ee1[j]][0]};
      coef2[j] <= {mat_coef[emat1[j]][5], mat_coef[emat1[j]][4], mat_coef[emat1[j]][3],
                   mat_coef[emat1[j]][2], mat_coef[emat1[j]][1], mat_coef[emat1[j]][0]};
      mflags2[j] <= mat_flags[emat1[j]];
      // gather 1: gather table
      gent1[j] <= gather_mem[GIdxW'(row_q * 24'(Lanes) + 24'(j))];
      // gather 2: edge force
      gent2[j] <= gent1[j];
      for (int i = 0; i < 3; i++) gf2[j][i] <= ef_mem[gent1[j][15:0]][i];
      // gather 3: accumulated sum to the MPM request
      midx3[j] <= gent2[j][16 +: PIdxW];
      for (int i = 0; i < 3; i++) mf3[j][i] <= acc_sat[j][i];
      // gather 4: particle memory
      midx4[j] <= midx3[j];
      mf4[j] <= {mf3[j][2], mf3[j][1], mf3[j][0]};
      mx4[j] <= {px_mem[midx3[j]][2], px_mem[midx3[j]][1], px_mem[midx3[j]][0]};
      mp4[j] <= {pp_mem[midx3[j]][2], pp_mem[midx3[j]][1], pp_mem[midx3[j]][0]};
      mx04[j] <= {x0_mem[midx3[j]][2], x0_mem[midx3[j]][1], x0_mem[midx3[j]][0]};
      mminv4[j] <= minv_mem[midx3[j]];
      mflags4[j] <= pflags_mem[midx3[j]];
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      for (int j = 0; j < Lanes; j++) begin
        ev1[j] <= 1'b0;
        ev2[j] <= 1'b0;
        gv1[j] <= 1'b0;
        gv2[j] <= 1'b0;
        mreq3[j] <= 1'b0;
        mreq4[j] <= 1'b0;
        for (int i = 0; i < 3; i++) acc_q[j][i] <= '0;
      end
    end else begin
      for (int j = 0; j < Lanes; j++) begin
        ev1[j] <= tem_issue && (row_q * 24'(Lanes) + 24'(j) < num_edges_q);
        ev2[j] <= ev1[j];
        gv1[j] <= gather_issue;
        gv2[j] <= gv1[j];
        mreq3[j] <= gv2[j] && gent2[j][30];
        mreq4[j] <= mreq3[j];
        for (int i = 0; i < 3; i++) begin
          if (gv2[j] && gent2[j][30]) acc_q[j][i] <= '0;
          else acc_q[j][i] <= acc_next[j][i];
        end
      end
    end
  end

  // ---------------------------------------------------------------- memory writes
  logic host_we;
  assign host_we = (state_q == StWData) && in_fire;
  always_ff @(posedge clk_i) begin
    // Host writes (only while idle: no overlap with the lanes' writes below).
    if (host_we) begin
      case (region_q)
        4'(rheo_consts_pkg::RegionParticleState): begin
          if (index_q < 24'(MaxParticles)) begin
            if (field_q < 3) px_mem[PIdxW'(index_q)][field_q[1:0]] <= s_axis_tdata;
            else pp_mem[PIdxW'(index_q)][2'(field_q - 3'd3)] <= s_axis_tdata;
          end
        end
        4'(rheo_consts_pkg::RegionParticleStatic): begin
          if (index_q < 24'(MaxParticles)) begin
            if (field_q < 3) x0_mem[PIdxW'(index_q)][field_q[1:0]] <= s_axis_tdata;
            else if (field_q == 3) minv_mem[PIdxW'(index_q)] <= s_axis_tdata[CoefW-1:0];
            else pflags_mem[PIdxW'(index_q)] <= s_axis_tdata[1:0];
          end
        end
        4'(rheo_consts_pkg::RegionEdge): begin
          if (index_q < 24'(MaxEdges)) begin
            case (field_q)
              3'd0: begin
                es_mem[EIdxW'(index_q)] <= s_axis_tdata[PIdxW-1:0];
                ee_mem[EIdxW'(index_q)] <= s_axis_tdata[16 +: PIdxW];
              end
              3'd1: elen_mem[EIdxW'(index_q)] <= s_axis_tdata;
              3'd2: ed_mem[EIdxW'(index_q)] <= s_axis_tdata;
              default: emat_mem[EIdxW'(index_q)] <= s_axis_tdata[MIdxW-1:0];
            endcase
          end
        end
        4'(rheo_consts_pkg::RegionMaterial): begin
          if (index_q < 24'(MaxMaterials)) begin
            if (field_q < 6) mat_coef[MIdxW'(index_q)][field_q] <= s_axis_tdata[CoefW-1:0];
            else mat_flags[MIdxW'(index_q)] <= s_axis_tdata[1:0];
          end
        end
        4'(rheo_consts_pkg::RegionGather): begin
          if (index_q < 24'(MaxGather)) gather_mem[GIdxW'(index_q)] <= s_axis_tdata[30:0];
        end
        4'(rheo_consts_pkg::RegionEdgeLength): begin
          if (index_q < 24'(MaxEdges)) ed_mem[EIdxW'(index_q)] <= s_axis_tdata;
        end
        default: ;
      endcase
    end
    // Lane writes: TEM results and MPM results.
    for (int j = 0; j < Lanes; j++) begin
      if (tem_valid[j]) begin
        for (int i = 0; i < 3; i++) ef_mem[tem_idx[j]][i] <= tem_f[j][i*W +: W];
        ed_mem[tem_idx[j]] <= tem_d[j];
      end
      if (mpm_valid[j]) begin
        for (int i = 0; i < 3; i++) begin
          px_mem[mpm_idx[j]][i] <= mpm_x[j][i*W +: W];
          pp_mem[mpm_idx[j]][i] <= mpm_p[j][i*W +: W];
        end
      end
    end
  end

  // ---------------------------------------------------------------- Maxwell arm memories
  // The arm's per-edge extension m follows d (fetched with the edge, written back with
  // the TEM result); the arm's coefficients follow the material table.
  if (MaxwellArm != 0) begin : g_arm_mem
    logic [W-1:0] em_mem [MaxEdges];
    logic [CoefW-1:0] mat_arm [MaxMaterials][2];
    logic [W-1:0] em1 [Lanes];
    always_ff @(posedge clk_i) begin
      if (host_we && region_q == 4'(rheo_consts_pkg::RegionMaterialArm) &&
          index_q < 24'(MaxMaterials))
        mat_arm[MIdxW'(index_q)][field_q[0]] <= s_axis_tdata[CoefW-1:0];
      if (host_we && region_q == 4'(rheo_consts_pkg::RegionEdgeArm) && index_q < 24'(MaxEdges))
        em_mem[EIdxW'(index_q)] <= s_axis_tdata;
      for (int j = 0; j < Lanes; j++) begin
        em1[j] <= em_mem[EIdxW'(row_q * 24'(Lanes) + 24'(j))];
        em2[j] <= em1[j];
        coef_arm2[j] <= {mat_arm[emat1[j]][1], mat_arm[emat1[j]][0]};
        if (tem_valid[j]) em_mem[tem_idx[j]] <= tem_m[j];
      end
    end
    assign arm_read_word = em_mem[EIdxW'(index_q)];
  end else begin : g_no_arm_mem
    logic unused_tem_m;
    always_comb begin
      unused_tem_m = 1'b0;
      for (int j = 0; j < Lanes; j++) begin
        em2[j] = '0;
        coef_arm2[j] = '0;
        unused_tem_m = unused_tem_m ^ (^tem_m[j]) ^ (^coef_arm2[j]);
      end
    end
    assign arm_read_word = '0;
  end

  // ---------------------------------------------------------------- read-back mux
  logic [W-1:0] read_word;
  always_comb begin
    read_word = '0;
    case (region_q)
      4'(rheo_consts_pkg::RegionParticleState): begin
        if (index_q < 24'(MaxParticles)) begin
          if (field_q < 3) read_word = px_mem[PIdxW'(index_q)][field_q[1:0]];
          else read_word = pp_mem[PIdxW'(index_q)][2'(field_q - 3'd3)];
        end
      end
      4'(rheo_consts_pkg::RegionEdgeLength): begin
        if (index_q < 24'(MaxEdges)) read_word = ed_mem[EIdxW'(index_q)];
      end
      4'(rheo_consts_pkg::RegionEdgeArm): begin
        if (MaxwellArm != 0 && index_q < 24'(MaxEdges)) read_word = arm_read_word;
      end
      default: read_word = '0;
    endcase
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
    for (int j = 0; j < Lanes; j++) begin
      if (tem_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusTemSat);
      if (tem_deg[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusDegenerate);
      if (mpm_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
      if (gv2[j] && gent2[j][30] && acc_clip[j])
        lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= StIdle;
      region_q <= '0;
      count_q <= '0;
      index_q <= '0;
      field_q <= '0;
      clear_q <= 1'b0;
      row_q <= '0;
      drain_q <= '0;
      out_data_q <= '0;
      out_valid_q <= 1'b0;
      out_last_q <= 1'b0;
      plate_acc_q <= '0;
      num_particles_q <= '0;
      num_edges_q <= '0;
      gather_rows_q <= '0;
      for (int i = 0; i < 3; i++) gravity_q[i] <= '0;
      floor_en_q <= 1'b0;
      plate_en_q <= 1'b0;
      plate_z_q <= '0;
      status_q <= '0;
      step_count_q <= '0;
      cycle_count_q <= '0;
    end else begin
      status_q <= status_q | lane_flags;
      plate_acc_q <= plate_sum;
      if (busy_o) cycle_count_q <= cycle_count_q + 32'd1;
      case (state_q)
        StIdle: begin
          if (in_fire) begin
            region_q <= s_axis_tdata[27:24];
            count_q <= s_axis_tdata[23:0];
            field_q <= '0;
            case (s_axis_tdata[31:28])
              4'(rheo_consts_pkg::OpWrite): begin
                if (s_axis_tdata[27:24] >= 4'(CoreRegions))
                  status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                else state_q <= StWStart;
              end
              4'(rheo_consts_pkg::OpRead): begin
                if (s_axis_tdata[27:24] >= 4'(CoreRegions))
                  status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                else state_q <= StRStart;
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
        StWStart: begin
          if (in_fire) begin
            index_q <= s_axis_tdata[23:0];
            state_q <= (count_q == 0) ? StIdle : StWData;
          end
        end
        StWData: begin
          if (in_fire) begin
            if (region_q == 4'(rheo_consts_pkg::RegionGlobals)) begin
              case (index_q)
                24'd0: num_particles_q <= s_axis_tdata[23:0];
                24'd1: num_edges_q <= s_axis_tdata[23:0];
                24'd2: gather_rows_q <= s_axis_tdata[23:0];
                24'd3: gravity_q[0] <= s_axis_tdata;
                24'd4: gravity_q[1] <= s_axis_tdata;
                24'd5: gravity_q[2] <= s_axis_tdata;
                24'd6: begin
                  floor_en_q <= s_axis_tdata[0];
                  plate_en_q <= s_axis_tdata[1];
                end
                default: status_q <= status_q | 32'(rheo_consts_pkg::StatusBadCommand);
              endcase
            end
            if (entry_done) begin
              field_q <= '0;
              index_q <= index_q + 24'd1;
              count_q <= count_q - 24'd1;
              if (count_q == 24'd1) state_q <= StIdle;
            end else begin
              field_q <= field_q + 3'd1;
            end
          end
        end
        StRStart: begin
          if (in_fire) begin
            index_q <= s_axis_tdata[23:0];
            state_q <= (count_q == 0) ? StIdle : StRFetch;
          end
        end
        StRFetch: begin
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
            plate_acc_q <= '0;
            row_q <= '0;
            state_q <= StTem;
          end
        end
        StTem: begin
          if (row_q + 24'd1 >= tem_rows) begin
            row_q <= '0;
            drain_q <= DrainW'(TemDrain - 1);
            state_q <= StTemDrain;
          end else begin
            row_q <= row_q + 24'd1;
          end
        end
        StTemDrain: begin
          if (drain_q == 0) state_q <= (gather_rows_q == 0) ? StMpmDrain : StGather;
          else drain_q <= drain_q - DrainW'(1);
          if (drain_q == 0) drain_q <= DrainW'(MpmDrain - 1);
        end
        StGather: begin
          if (row_q + 24'd1 >= gather_rows_q) begin
            row_q <= '0;
            drain_q <= DrainW'(MpmDrain - 1);
            state_q <= StMpmDrain;
          end else begin
            row_q <= row_q + 24'd1;
          end
        end
        StMpmDrain: begin
          if (drain_q == 0) begin
            out_data_q <= rheo_consts_pkg::sat_word(WideW'(plate_sum));
            if (rheo_consts_pkg::clips(WideW'(plate_sum), W))
              status_q <= status_q | lane_flags | 32'(rheo_consts_pkg::StatusPlateSat);
            out_valid_q <= 1'b1;
            out_last_q <= (count_q == 24'd1);
            step_count_q <= step_count_q + 32'd1;
            state_q <= StForceOut;
          end else begin
            drain_q <= drain_q - DrainW'(1);
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
