// Rheological-object core: particle and edge state in on-chip memories, Lanes parallel
// TEM and MPM lanes, and an AXI4-Stream style command interface (format in
// hls/frame_format.hpp, constants in rheo_consts_pkg).
//
// Partitioning: particle i lives in bank i % Lanes at local address i / Lanes; edge slot t
// (host index) belongs to lane t % Lanes, row t / Lanes. The host (make_core_image)
// puts every edge in a slot of the lane whose bank holds its start particle and
// schedules the rows so that the end particles of one row lie in pairwise different banks
// (empty slots are bubbles). After reset the core clears its force sums (MaxParticles / Lanes
// clocks, input not ready). The command FSM keeps bank / local counters (an
// IdxCountW-clock shift-subtract division turns a command's start index into them).
//
// One step (after the plate-height word arrives):
//   edge pass: row r = 0 .. R-1; lane j reads slot (r, j), its start particle from its own
//              bank (port A) and its end particle through an L x L crossbar (port B of
//              the end's bank), runs its TEM, writes d (and the arms' m) back and adds +F
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
//
// Files (one job each; this module only wires them and holds the lanes' pipeline
// registers between them):
//   rheo_core_ctrl.sv      command decoder and step sequencer, every control register
//   rheo_core_mem_bank.sv  particle bank: x / p, x0 / minv / flags, the two force sums
//   rheo_core_mem_edge.sv  edge slots of one lane
//   rheo_core_mem_mat.sv   material table
//   rheo_core_xbar.sv      end-particle crossbar (addresses, words, force sums)
//   rheo_core_readback.sv  READ command's word from the memories
//   rheo_core_plate_acc.sv plate force of a step
//   rheo_tem.sv, rheo_mpm.sv the lanes' edge and mass-point modules
//   rheo_tool.sv           the lanes' tool units (ToolContact)
// MaxwellArms = K (1..rheo_consts_pkg::MaxArms) builds the variant with K parallel Maxwell
// arms in every TEM: per edge slot and arm j the arm's extension m_j (region EdgeArm + 2 j,
// read and written like d) and per material gamma_j and k2t_j (region MaterialArm + 2 j).
// Same cycles per step. MaxwellArms = 0 is the baseline core; the regions of arms the
// core does not have are refused as bad commands.
// SeriesDamper = 1 builds the variant with the force-dependent series damper in every TEM
// (rheo_damper): per material six more coefficients (region MaterialDamper). Same cycles
// per step; a core without it refuses the region.
// StrainHardening = 1 builds the variant with strain hardening in every TEM (rheo_harden):
// per material three more coefficients (region MaterialHardening). Its TEM runs
// HardTemExtra clocks longer (HardDamperTemExtra with the damper too), and so does the edge
// pass's drain (the TEM drain of the cycle formula); a core without it refuses the region.
// With arms it needs the damper as well (the element with every effect).
// VolumePreservation = 1 builds the variant with a volume element unit per lane
// (rheo_volume): a tetrahedron takes two consecutive slots of a lane (record bits element
// and second half), its vertices a, b read as the first slot's start and end particles and
// c, d as the second's; the unit's forces come out in the TEM's output clocks of the two
// slots (it has the TEM's latency) and are added to the four particles' sums through the
// same accumulator ports. The TEM sees neither slot. Same cycles per step for the same
// rows; the host schedules the elements' rows after the edges' (make_core_image). A second
// half that does not follow a first half in the lane's previous row, or an element slot on
// a core without the unit, is a schedule conflict.
// ToolContact = 1 builds the variant with a tool unit per lane (rheo_tool): each particle
// the MPM pass reads meets one rigid tool (plane, sphere or cylinder, penalty force with
// Coulomb friction) whose registers the host writes before a step (region RegionTool). The unit
// takes the particle's x and p at MPM stage 3, its other MPM inputs wait for it in a delay
// line, and its force (none for fixed particles) joins the force sum, saturated once more,
// in one more stage: the MPM pass runs ToolLatency + 1 clocks longer, and so does its drain
// (the MPM drain of the cycle formula). The sums of the tool's forces (exact, PlateAccW
// bits per axis) give the reaction force a READ of region RegionToolReaction returns.
module rheo_core #(
  parameter int Lanes = 1,              // parallel TEM/MPM lanes and banks (1..4)
  parameter int MaxParticles = 4096,    // particle memory depth (all banks)
  parameter int MaxEdges = 65536,       // edge slots (all lanes, bubbles included)
  parameter int MaxMaterials = 16,      // material table depth
  parameter int W = 32,                 // stream and state word width
  parameter int CoefW = 24,             // packed coefficient width
  parameter int MaxwellArms = 0,        // parallel Maxwell arms per TEM (0..MaxArms)
  parameter int SeriesDamper = 0,       // force-dependent series damper in every TEM (0/1)
  parameter int StrainHardening = 0,    // strain hardening in every TEM (0/1)
  parameter int VolumePreservation = 0, // a volume element unit per lane (0/1)
  parameter int ToolContact = 0         // a tool unit per lane in the MPM pass (0/1)
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
  localparam int AccW = rheo_consts_pkg::ForceAccW;
  localparam int SumW = AccW + 1;  // start sum + end sum
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW;
  localparam int NumCoef = rheo_consts_pkg::MaterialCoefs +
                           ((SeriesDamper != 0) ? rheo_consts_pkg::DamperCoefs : 0) +
                           ((StrainHardening != 0) ? rheo_consts_pkg::HardeningCoefs : 0) +
                           rheo_consts_pkg::MaterialArmCoefs * MaxwellArms;
  localparam int ArmW = ((MaxwellArms > 0) ? MaxwellArms : 1) * W;  // a slot's m words
  localparam int XpWords = rheo_consts_pkg::ParticleStateWords;  // {p, x}
  localparam int XpW = XpWords * W;
  localparam int MFlagsW = rheo_consts_pkg::MatFlagsW;
  localparam int PFlagsW = rheo_consts_pkg::ParticleFlagsW;
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW;
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits;
  localparam int FieldW = rheo_consts_pkg::EntryFieldW;
  // Edge slot record: {valid, element, second half, end bank, end local, start local}.
  localparam int RecW = 3 + EBW + 2 * PAW;
  // The TEM's latency, which the volume element unit matches (rheo_tem's Last + 1).
  localparam int TemLat = rheo_consts_pkg::TemLatency +
                          ((StrainHardening == 0) ? 0
                           : ((SeriesDamper != 0) ? rheo_consts_pkg::HardDamperTemExtra
                                                  : rheo_consts_pkg::HardTemExtra));
  // Carried through the TEM: {row, start local, end bank, end local}.
  localparam int TemIdxW = EAW + PAW + BW + PAW;
  localparam int B = rheo_consts_pkg::OperandBits;

  if (W != rheo_consts_pkg::Width || CoefW != rheo_consts_pkg::CoefW) begin : g_check
    $error("rheo_core: W/CoefW must match rheo_consts_pkg");
  end
  if (Lanes < 1 || Lanes > 4) begin : g_lanes_check
    $error("rheo_core: Lanes must be 1..4");
  end
  if (PAW > rheo_consts_pkg::EdgeLocalBits) begin : g_depth_check
    $error("rheo_core: particles per bank exceed the edge word's local address field");
  end

  // ---------------------------------------------------------------- controller
  logic host_we, host_wdata, particle_ok, edge_ok;
  logic [RegionW-1:0] region;
  logic [FieldW-1:0] field;
  logic [IdxCountW-1:0] index, local_addr, row;
  logic [BW-1:0] bank;
  logic clearing_sums, tem_pass, edge_phase, mpm_phase, edge_issue, plate_start;
  logic [Lanes-1:0] mpm_issue;
  logic [3*W-1:0] gravity;
  logic floor_en, plate_en, hold_en, prev_valid;
  // The controller's registers under the names the waveform view (host/driver/gtkw.cpp)
  // shows at the core's scope.
  logic [W-1:0] plate_z_q;
  logic [W-1:0] plate_prev;
  logic [W-1:0] read_word;
  logic [31:0] lane_flags;
  logic [PlateAccW-1:0] plate_acc;
  // The tool unit's registers (from the controller) and the sums of its forces.
  logic [1:0] tool_kind;
  logic [3*W-1:0] tool_c, tool_dc;
  logic [3*B-1:0] tool_a;
  logic [W-1:0] tool_reach, tool_half_len;
  logic [CoefW-1:0] tool_kt, tool_ct, tool_mu, tool_spin;
  logic [3*PlateAccW-1:0] tool_acc;

  rheo_core_ctrl #(
    .Lanes(Lanes), .MaxParticles(MaxParticles), .PDepth(PDepth), .EDepth(EDepth), .W(W),
    .MaxwellArms(MaxwellArms), .SeriesDamper(SeriesDamper), .StrainHardening(StrainHardening),
    .ToolContact(ToolContact)
  ) u_ctrl (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast), .busy_o(busy_o),
    .host_we_o(host_we), .host_wdata_o(host_wdata), .region_o(region), .field_o(field),
    .index_o(index), .local_o(local_addr), .bank_o(bank), .particle_ok_o(particle_ok),
    .edge_ok_o(edge_ok),
    .row_o(row), .clearing_sums_o(clearing_sums), .tem_pass_o(tem_pass),
    .edge_phase_o(edge_phase), .mpm_phase_o(mpm_phase), .edge_issue_o(edge_issue),
    .mpm_issue_o(mpm_issue), .plate_start_o(plate_start),
    .gravity_o(gravity), .floor_en_o(floor_en), .plate_en_o(plate_en), .plate_z_o(plate_z_q),
    .hold_en_o(hold_en), .prev_valid_o(prev_valid), .plate_prev_o(plate_prev),
    .read_word_i(read_word), .lane_flags_i(lane_flags), .plate_acc_i(plate_acc),
    .tool_kind_o(tool_kind), .tool_c_o(tool_c), .tool_dc_o(tool_dc), .tool_a_o(tool_a),
    .tool_reach_o(tool_reach), .tool_half_len_o(tool_half_len), .tool_kt_o(tool_kt),
    .tool_ct_o(tool_ct), .tool_mu_o(tool_mu), .tool_spin_o(tool_spin), .tool_acc_i(tool_acc));

  // ---------------------------------------------------------------- lane signals
  // Edge pass, stage 1 (slot record read) and stage 2 (particles read, TEM input).
  logic ev1_q;
  logic [EAW-1:0] row1_q;
  logic [RecW-1:0] rec1 [Lanes];
  logic [Lanes-1:0] valid1;
  // Volume elements: the slot is an element half (elem1), its second half (second1); a
  // first half was issued in the lane's previous row (pend_q); halves the unit takes.
  logic [Lanes-1:0] elem1, second1, pend_q, vol_take1, elem_conflict;
  logic vv2_q [Lanes], vsec2_q [Lanes];
  logic [Lanes-1:0] vol_valid;
  logic vol_sat [Lanes];
  logic [Lanes*3*W-1:0] vol_fs, vol_fe, res_f, res_fe;
  logic [Lanes-1:0] res_valid;
  logic [PAW-1:0] s_local1 [Lanes];
  logic [Lanes*PAW-1:0] e_local1;
  logic [Lanes*EBW-1:0] e_bank1;
  logic [W-1:0] len1 [Lanes], d1 [Lanes];
  logic [ArmW-1:0] m1 [Lanes];
  logic [Lanes*MIdxW-1:0] mat1;
  logic ev2_q [Lanes];
  logic [TemIdxW-1:0] idx2_q [Lanes];
  logic [W-1:0] len2_q [Lanes], d2_q [Lanes];
  logic [ArmW-1:0] m2_q [Lanes];
  logic [Lanes*BW-1:0] eb2_q;
  logic [Lanes*NumCoef*CoefW-1:0] tem_coef;
  logic [Lanes*MFlagsW-1:0] mflags2;
  logic [Lanes*XpW-1:0] end_xp2;
  logic schedule_conflict;
  // TEM outputs.
  logic [Lanes-1:0] tem_valid;
  logic tem_sat [Lanes], tem_deg [Lanes];
  logic [TemIdxW-1:0] tem_idx [Lanes];
  logic [Lanes*3*W-1:0] tem_f;
  logic [W-1:0] tem_d [Lanes];
  logic [ArmW-1:0] tem_m [Lanes];
  logic [EAW-1:0] tem_row [Lanes];
  logic [Lanes*PAW-1:0] tem_s_local, tem_e_local;
  logic [Lanes*BW-1:0] tem_e_bank;
  // Particle banks: memory ports, lane / bank j at [j*n +: n] (flat: Yosys 0.23
  // mis-connects instance ports to elements of two-dimensional unpacked arrays).
  logic [Lanes*XpW-1:0] xp_a_data, xp_b_data;
  logic [Lanes*PAW-1:0] xbar_addr;
  // Accumulator additions per bank: start side from the own lane, end side via crossbar.
  logic [Lanes-1:0] acc_s_valid, acc_e_valid;
  logic [Lanes*PAW-1:0] acc_s_addr, acc_e_addr;
  logic [Lanes*3*AccW-1:0] acc_s_val, acc_e_val;
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
  logic [PFlagsW-1:0] pflags_data [Lanes];
  logic [3*SumW-1:0] total1 [Lanes], mtotal2_q [Lanes];
  logic [3*W-1:0] f2 [Lanes];
  logic clip2 [Lanes];
  logic [3*W-1:0] mx2_q [Lanes], mp2_q [Lanes], mx02_q [Lanes];
  logic [3*W-1:0] mf3_q [Lanes], mx3_q [Lanes], mp3_q [Lanes], mx03_q [Lanes];
  logic [CoefW-1:0] mminv2_q [Lanes], mminv3_q [Lanes];
  logic [PFlagsW-1:0] mflags2m_q [Lanes], mflags3m_q [Lanes];
  // MPM inputs: stage 3's registers, or (ToolContact) the stage after the tool unit.
  logic mpm_in_valid [Lanes];
  logic [PAW-1:0] mpm_in_idx [Lanes];
  logic [3*W-1:0] mpm_in_f [Lanes], mpm_in_x [Lanes], mpm_in_p [Lanes], mpm_in_x0 [Lanes];
  logic [CoefW-1:0] mpm_in_minv [Lanes];
  logic [PFlagsW-1:0] mpm_in_flags [Lanes];
  logic tool_flag [Lanes];  // the tool unit or its sum stage saturated (MPM saturation)
  logic [Lanes-1:0] tool_push;  // lane j's tool force of this clock enters the reaction
  logic [Lanes*3*W-1:0] tool_push_f;
  logic [Lanes-1:0] mpm_valid;
  logic mpm_sat [Lanes];
  logic [PAW-1:0] mpm_idx [Lanes];
  logic [3*W-1:0] mpm_x [Lanes], mpm_p [Lanes];
  logic [Lanes*W-1:0] mpm_plate_f;
  // Edge slot memories of each lane (read port data).
  logic [Lanes*W-1:0] d_a_data;
  logic [Lanes*ArmW-1:0] m_a_data;

  // The controller counts entries and rows in IdxCountW bits; the memories take the low
  // address bits (particle_ok / edge_ok and the global registers' limits cover the rest).
  logic unused_addr_bits;
  assign unused_addr_bits = ^{local_addr, row};

  logic [PAW-1:0] clear_addr;
  assign clear_addr = clearing_sums ? PAW'(row) : walk1_q;

  // ---------------------------------------------------------------- lanes
  for (genvar j = 0; j < Lanes; j++) begin : g_lane
    // ---- edge slots ----
    rheo_core_mem_edge #(
      .W(W), .EDepth(EDepth), .PAW(PAW), .MaxMaterials(MaxMaterials), .MaxwellArms(MaxwellArms)
    ) u_edges (
      .clk_i(clk_i), .tem_pass_i(tem_pass), .row_i(EAW'(row)), .host_addr_i(EAW'(local_addr)),
      .host_we_i(host_we && bank == BW'(j) && edge_ok), .region_i(region), .field_i(field),
      .wdata_i(s_axis_tdata),
      .wb_valid_i(tem_valid[j]), .wb_row_i(tem_row[j]), .wb_d_i(tem_d[j]), .wb_m_i(tem_m[j]),
      .rec_o(rec1[j]), .len_o(len1[j]), .d_o(d_a_data[j*W +: W]),
      .mat_o(mat1[j*MIdxW +: MIdxW]), .m_o(m_a_data[j*ArmW +: ArmW]));
    assign d1[j] = d_a_data[j*W +: W];
    assign m1[j] = m_a_data[j*ArmW +: ArmW];

    // ---- edge pass stage 1: the slot's particles ----
    assign valid1[j] = ev1_q && rec1[j][RecW-1];
    assign elem1[j] = rec1[j][RecW-2];
    assign second1[j] = rec1[j][RecW-3];
    // The unit takes a first half, and a second half right after its first half
    // (hls::core_step's rule); anything else with the element bit is a conflict.
    assign vol_take1[j] = (VolumePreservation != 0) && valid1[j] && elem1[j] &&
                          (!second1[j] || pend_q[j]);
    assign elem_conflict[j] = valid1[j] && elem1[j] && !vol_take1[j];
    assign e_bank1[j*EBW +: EBW] = rec1[j][2*PAW +: EBW];
    assign e_local1[j*PAW +: PAW] = rec1[j][PAW +: PAW];
    assign s_local1[j] = rec1[j][PAW-1:0];

    // ---- edge pass stage 2: TEM (start from the own bank, end via the crossbar) ----
    rheo_tem #(.W(W), .CoefW(CoefW), .IdxW(TemIdxW), .MaxwellArms(MaxwellArms),
               .SeriesDamper(SeriesDamper), .StrainHardening(StrainHardening)) u_tem (
      .clk_i       (clk_i),
      .rst_ni      (rst_ni),
      .valid_i     (ev2_q[j]),
      .idx_i       (idx2_q[j]),
      .xs_i        (xp_a_data[j*XpW +: 3*W]),
      .xe_i        (end_xp2[j*XpW +: 3*W]),
      .ps_i        (xp_a_data[j*XpW + 3*W +: 3*W]),
      .pe_i        (end_xp2[j*XpW + 3*W +: 3*W]),
      .d_i         (d2_q[j]),
      .len_i       (len2_q[j]),
      .m_i         (m2_q[j]),
      .coef_i      (tem_coef[j*NumCoef*CoefW +: NumCoef*CoefW]),
      .mat_flags_i (mflags2[j*MFlagsW +: MFlagsW]),
      .valid_o     (tem_valid[j]),
      .idx_o       (tem_idx[j]),
      .f_o         (tem_f[j*3*W +: 3*W]),
      .d_o         (tem_d[j]),
      .m_o         (tem_m[j]),
      .sat_o       (tem_sat[j]),
      .degenerate_o(tem_deg[j])
    );
    assign {tem_row[j], tem_s_local[j*PAW +: PAW], tem_e_bank[j*BW +: BW],
            tem_e_local[j*PAW +: PAW]} = tem_idx[j];

    // ---- edge pass stage 2: volume element unit (the TEM's latency, so that its two
    // beats take the output clocks of the element's two slots; the TEM's index delay line
    // carries their particle addresses) ----
    if (VolumePreservation != 0) begin : g_vol
      rheo_volume #(.Latency(TemLat)) u_vol (
        .clk_i   (clk_i),
        .rst_ni  (rst_ni),
        .valid_i (vv2_q[j]),
        .second_i(vsec2_q[j]),
        .xs_i    (xp_a_data[j*XpW +: 3*W]),
        .xe_i    (end_xp2[j*XpW +: 3*W]),
        .l_i     (len2_q[j]),
        .d_i     (d2_q[j]),
        .valid_o (vol_valid[j]),
        .fs_o    (vol_fs[j*3*W +: 3*W]),
        .fe_o    (vol_fe[j*3*W +: 3*W]),
        .sat_o   (vol_sat[j]));
    end else begin : g_no_vol
      assign vol_valid[j] = 1'b0;
      assign vol_fs[j*3*W +: 3*W] = '0;
      assign vol_fe[j*3*W +: 3*W] = '0;
      assign vol_sat[j] = 1'b0;
      logic unused_vol;
      assign unused_vol = vv2_q[j] ^ vsec2_q[j];
    end
    // A slot's result: the TEM's force (+F to the start, -F to the end) or the element's
    // two forces. The two never share a clock (each slot feeds one of them).
    assign res_valid[j] = tem_valid[j] || vol_valid[j];
    assign res_f[j*3*W +: 3*W] = vol_valid[j] ? vol_fs[j*3*W +: 3*W] : tem_f[j*3*W +: 3*W];
    assign res_fe[j*3*W +: 3*W] = vol_fe[j*3*W +: 3*W];

    // ---- particle bank j ----
    rheo_core_mem_bank #(.W(W), .CoefW(CoefW), .PDepth(PDepth)) u_bank (
      .clk_i(clk_i), .rst_ni(rst_ni),
      .mpm_phase_i(mpm_phase), .edge_phase_i(edge_phase), .row_i(PAW'(row)),
      .start_local_i(s_local1[j]), .xbar_addr_i(xbar_addr[j*PAW +: PAW]),
      .host_wdata_i(host_wdata), .host_we_i(host_we && bank == BW'(j) && particle_ok),
      .host_addr_i(PAW'(local_addr)), .region_i(region), .field_i(field),
      .wdata_i(s_axis_tdata),
      .mpm_valid_i(mpm_valid[j]), .mpm_idx_i(mpm_idx[j]), .mpm_x_i(mpm_x[j]),
      .mpm_p_i(mpm_p[j]),
      .xp_a_o(xp_a_data[j*XpW +: XpW]), .xp_b_o(xp_b_data[j*XpW +: XpW]),
      .x0_o(x0_data[j]), .minv_o(minv_data[j]), .pflags_o(pflags_data[j]),
      .acc_s_valid_i(acc_s_valid[j]), .acc_s_addr_i(acc_s_addr[j*PAW +: PAW]),
      .acc_s_val_i(acc_s_val[j*3*AccW +: 3*AccW]),
      .acc_e_valid_i(acc_e_valid[j]), .acc_e_addr_i(acc_e_addr[j*PAW +: PAW]),
      .acc_e_val_i(acc_e_val[j*3*AccW +: 3*AccW]),
      .clear_i(mv1_q[j] || clearing_sums), .clear_addr_i(clear_addr),
      .sum_s_o(sum_s[j]), .sum_e_o(sum_e[j]));

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

    // ---- MPM pass stage 3 + ToolLatency (ToolContact): the tool's force joins the sum ----
    if (ToolContact != 0) begin : g_tool
      logic tool_valid, tool_contact, tool_sat;
      logic [PAW-1:0] tool_idx;
      logic [3*W-1:0] tool_f;
      rheo_tool #(.W(W), .CoefW(CoefW), .IdxW(PAW)) u_tool (
        .clk_i(clk_i), .rst_ni(rst_ni), .valid_i(mreq3_q[j]), .idx_i(midx3_q[j]),
        .x_i(mx3_q[j]), .p_i(mp3_q[j]), .minv_i(mminv3_q[j]),
        .kind_i(tool_kind), .c_i(tool_c), .dc_i(tool_dc), .a_i(tool_a), .reach_i(tool_reach),
        .half_len_i(tool_half_len), .kt_i(tool_kt), .ct_i(tool_ct), .mu_i(tool_mu),
        .spin_i(tool_spin),
        .valid_o(tool_valid), .idx_o(tool_idx), .f_o(tool_f), .contact_o(tool_contact),
        .sat_o(tool_sat));
      // The particle's other MPM inputs wait for the unit (distributed-RAM delay lines).
      localparam int WaitW = 12 * W + CoefW + PFlagsW;
      logic [WaitW-1:0] wait_in, wait_out;
      assign wait_in = {mf3_q[j], mx3_q[j], mp3_q[j], mx03_q[j], mminv3_q[j], mflags3m_q[j]};
      rheo_delay #(.W(WaitW), .N(rheo_consts_pkg::ToolLatency)) u_wait (
        .clk_i(clk_i), .rst_ni(rst_ni), .d_i(wait_in), .q_o(wait_out));
      logic [3*W-1:0] wf, wx, wp, wx0;
      logic [CoefW-1:0] wminv;
      logic [PFlagsW-1:0] wflags;
      assign {wf, wx, wp, wx0, wminv, wflags} = wait_out;
      // A fixed particle does not meet the tool (the reference model skips it).
      logic pushes;
      assign pushes = tool_valid && tool_contact && !wflags[0];
      assign tool_push[j] = pushes;
      assign tool_push_f[j*3*W +: 3*W] = tool_f;
      logic signed [W:0] fsum [3];
      logic fclip;
      always_comb begin
        fclip = 1'b0;
        for (int i = 0; i < 3; i++) begin
          fsum[i] = (W+1)'($signed(wf[i*W +: W])) +
                    (pushes ? (W+1)'($signed(tool_f[i*W +: W])) : '0);
          fclip = fclip | (fsum[i][W] ^ fsum[i][W-1]);
        end
      end
      logic vt_q, flag_q;
      logic [PAW-1:0] idxt_q;
      logic [3*W-1:0] ft_q, xt_q, pt_q, x0t_q;
      logic [CoefW-1:0] minvt_q;
      logic [PFlagsW-1:0] flagst_q;
      always_ff @(posedge clk_i or negedge rst_ni) begin
        if (!rst_ni) begin
          vt_q <= 1'b0;
          flag_q <= 1'b0;
        end else begin
          vt_q <= tool_valid;
          flag_q <= tool_valid && !wflags[0] && (tool_sat || fclip);
        end
      end
      always_ff @(posedge clk_i) begin
        idxt_q <= tool_idx;
        for (int i = 0; i < 3; i++) begin
          if (fsum[i][W] ^ fsum[i][W-1]) ft_q[i*W +: W] <= {fsum[i][W], {(W-1){~fsum[i][W]}}};
          else ft_q[i*W +: W] <= fsum[i][W-1:0];
        end
        xt_q <= wx;
        pt_q <= wp;
        x0t_q <= wx0;
        minvt_q <= wminv;
        flagst_q <= wflags;
      end
      assign mpm_in_valid[j] = vt_q;
      assign mpm_in_idx[j] = idxt_q;
      assign mpm_in_f[j] = ft_q;
      assign mpm_in_x[j] = xt_q;
      assign mpm_in_p[j] = pt_q;
      assign mpm_in_x0[j] = x0t_q;
      assign mpm_in_minv[j] = minvt_q;
      assign mpm_in_flags[j] = flagst_q;
      assign tool_flag[j] = flag_q;
    end else begin : g_no_tool
      assign mpm_in_valid[j] = mreq3_q[j];
      assign mpm_in_idx[j] = midx3_q[j];
      assign mpm_in_f[j] = mf3_q[j];
      assign mpm_in_x[j] = mx3_q[j];
      assign mpm_in_p[j] = mp3_q[j];
      assign mpm_in_x0[j] = mx03_q[j];
      assign mpm_in_minv[j] = mminv3_q[j];
      assign mpm_in_flags[j] = mflags3m_q[j];
      assign tool_flag[j] = 1'b0;
      assign tool_push[j] = 1'b0;
      assign tool_push_f[j*3*W +: 3*W] = '0;
    end

    rheo_mpm #(.W(W), .CoefW(CoefW), .IdxW(PAW)) u_mpm (
      .clk_i     (clk_i),
      .rst_ni    (rst_ni),
      .valid_i   (mpm_in_valid[j]),
      .idx_i     (mpm_in_idx[j]),
      .f_i       (mpm_in_f[j]),
      .x_i       (mpm_in_x[j]),
      .p_i       (mpm_in_p[j]),
      .x0_i      (mpm_in_x0[j]),
      .minv_i    (mpm_in_minv[j]),
      .flags_i   (mpm_in_flags[j]),
      .g_i       (gravity),
      .plate_z_i (plate_z_q),
      .plate_en_i(plate_en),
      .floor_en_i(floor_en),
      .hold_en_i (hold_en),
      .prev_valid_i(prev_valid),
      .plate_prev_i(plate_prev),
      .valid_o   (mpm_valid[j]),
      .idx_o     (mpm_idx[j]),
      .x_o       (mpm_x[j]),
      .p_o       (mpm_p[j]),
      .plate_f_o (mpm_plate_f[j*W +: W]),
      .sat_o     (mpm_sat[j])
    );
  end

  // ---------------------------------------------------------------- shared datapath
  rheo_core_mem_mat #(
    .Lanes(Lanes), .MaxMaterials(MaxMaterials), .CoefW(CoefW), .MaxwellArms(MaxwellArms),
    .SeriesDamper(SeriesDamper), .StrainHardening(StrainHardening)
  ) u_mat (
    .clk_i(clk_i), .host_we_i(host_we), .region_i(region), .index_i(index), .field_i(field),
    .wdata_i(s_axis_tdata[CoefW-1:0]), .mat_i(mat1), .coef_o(tem_coef), .flags_o(mflags2));

  rheo_core_xbar #(.Lanes(Lanes), .W(W), .PAW(PAW)) u_xbar (
    .valid1_i(valid1), .e_bank1_i(e_bank1), .e_local1_i(e_local1),
    .xbar_addr_o(xbar_addr), .conflict_o(schedule_conflict),
    .xp_b_i(xp_b_data), .eb2_i(eb2_q), .end_xp_o(end_xp2),
    .tem_valid_i(res_valid), .tem_f_i(res_f), .tem_elem_i(vol_valid), .tem_fe_i(res_fe),
    .tem_s_local_i(tem_s_local),
    .tem_e_bank_i(tem_e_bank), .tem_e_local_i(tem_e_local),
    .acc_s_valid_o(acc_s_valid), .acc_s_addr_o(acc_s_addr), .acc_s_val_o(acc_s_val),
    .acc_e_valid_o(acc_e_valid), .acc_e_addr_o(acc_e_addr), .acc_e_val_o(acc_e_val));

  rheo_core_readback #(.Lanes(Lanes), .W(W), .MaxwellArms(MaxwellArms)) u_readback (
    .clk_i(clk_i), .region_i(region), .bank_i(bank), .field_i(field),
    .particle_ok_i(particle_ok), .edge_ok_i(edge_ok),
    .xp_a_i(xp_a_data), .d_i(d_a_data), .m_i(m_a_data), .word_o(read_word));

  rheo_core_plate_acc #(.Lanes(Lanes), .W(W)) u_plate (
    .clk_i(clk_i), .start_i(plate_start), .valid_i(mpm_valid), .plate_f_i(mpm_plate_f),
    .acc_o(plate_acc));

  // The tool's forces of a step, per axis (the plate accumulator's adder, three times).
  if (ToolContact != 0) begin : g_tool_acc
    for (genvar i = 0; i < 3; i++) begin : g_axis
      logic [Lanes*W-1:0] axis_f;
      for (genvar j = 0; j < Lanes; j++) begin : g_lane_f
        assign axis_f[j*W +: W] = tool_push_f[j*3*W + i*W +: W];
      end
      rheo_core_plate_acc #(.Lanes(Lanes), .W(W)) u_acc (
        .clk_i(clk_i), .start_i(plate_start), .valid_i(tool_push), .plate_f_i(axis_f),
        .acc_o(tool_acc[i*PlateAccW +: PlateAccW]));
    end
  end else begin : g_no_tool_acc
    assign tool_acc = '0;
    logic unused_tool;
    assign unused_tool = ^{tool_kind, tool_c, tool_dc, tool_a, tool_reach, tool_half_len, tool_kt,
                           tool_ct, tool_mu, tool_spin, tool_push, tool_push_f};
  end

  // Status flags the lanes raise this clock (the controller makes them sticky).
  always_comb begin
    lane_flags = '0;
    if (schedule_conflict || (|elem_conflict))
      lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusScheduleConflict);
    for (int j = 0; j < Lanes; j++) begin
      if (vol_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusVolumeSat);
      if (tem_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusTemSat);
      if (tem_deg[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusDegenerate);
      if (mpm_sat[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
      if (mclip3_q[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
      if (tool_flag[j]) lane_flags = lane_flags | 32'(rheo_consts_pkg::StatusMpmSat);
    end
  end

  // ---------------------------------------------------------------- pipeline registers
  always_ff @(posedge clk_i) begin
    row1_q <= EAW'(row);
    walk1_q <= PAW'(row);
    for (int j = 0; j < Lanes; j++) begin
      // Edge pass stage 1 -> 2.
      idx2_q[j] <= {row1_q, s_local1[j], BW'(e_bank1[j*EBW +: EBW]), e_local1[j*PAW +: PAW]};
      eb2_q[j*BW +: BW] <= BW'(e_bank1[j*EBW +: EBW]);
      len2_q[j] <= len1[j];
      d2_q[j] <= d1[j];
      m2_q[j] <= m1[j];
      // MPM pass stage 1 -> 2.
      midx2_q[j] <= walk1_q;
      mtotal2_q[j] <= total1[j];
      mx2_q[j] <= xp_a_data[j*XpW +: 3*W];
      mp2_q[j] <= xp_a_data[j*XpW + 3*W +: 3*W];
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
      pend_q <= '0;
      for (int j = 0; j < Lanes; j++) begin
        ev2_q[j] <= 1'b0;
        vv2_q[j] <= 1'b0;
        vsec2_q[j] <= 1'b0;
        mv1_q[j] <= 1'b0;
        mreq2_q[j] <= 1'b0;
        mreq3_q[j] <= 1'b0;
        mclip3_q[j] <= 1'b0;
      end
    end else begin
      ev1_q <= edge_issue;
      pend_q <= valid1 & elem1 & ~second1;
      for (int j = 0; j < Lanes; j++) begin
        ev2_q[j] <= valid1[j] && !elem1[j];
        vv2_q[j] <= vol_take1[j];
        vsec2_q[j] <= second1[j];
        mv1_q[j] <= mpm_issue[j];
        mreq2_q[j] <= mv1_q[j];
        mreq3_q[j] <= mreq2_q[j];
        mclip3_q[j] <= mreq2_q[j] && clip2[j];
      end
    end
  end
endmodule
