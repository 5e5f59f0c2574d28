// One lane of the sweep core (rtl/rheo_sweep_core.sv, docs/sweep_core.md): its slab of
// particles, its stream of edges (rheo_sweep_enum), a TEM, the force sums and an MPM that
// runs beside the sweep. Clock by clock, for a slot in the slot registers in clock E
// (edges and padding alike; every slot takes the same path):
//   E      the edge's SRAM word is read (the slot's word: device n % 2, address n / 2;
//          rheo_zbt_port: word at E+4)
//   E+1    the offset o_k; E+2 the end's local index e = s + o_k (own) or o_k - (ghost - a)
//          (cross)
//   E+3    memory addresses: the end particle (x/p port A); a particle's first slot also
//          reads the start (own: x/p port B; cross: the ghost copy)
//   E+4    x and p of both ends and the SRAM word: its class goes to the class table; an
//          own particle's x, p and static fields enter the MPM queue
//   E+5    the TEM's input: operands, d, and L from the class table; the class's material
//          index waits TemLateCoefClocks - 1 clocks, so that the material table's
//          coefficients reach the TEM when its products need them (rheo_tem LateCoef)
//   E+45   the TEM's force f and new d (TemLatency later): d goes back to the slot's word
//          (an odd number of clocks after its read, so it never meets a read in a device);
//          f is added to the particle's start sum (a register, cleared at its first slot)
//          and -f to the end's sum (rheo_sweep_end_sums, started afresh by a first edge)
//   E+46   a particle's last slot: its start sum is complete. Cross: written to the ghost
//          sums (the lane below adds it). Own: the end sum (window copy B), the lane
//          above's ghost sum and the queued static fields are read
//   E+47   start + end sum; E+48 + the lane above's ghost sum (exact); E+49 saturated
//   E+50   the MPM's input (with the queued x and p); E+58 its output: x and p go to the
//          slab (x/p port B, the clock after, or one later when a start read has the port)
//          and, for a particle the lane above keeps a ghost copy of, to that copy; its plate
//          force to the top
// A lane's last slot in clock E therefore has its x and p written by clock E+60 and its
// plate force in the top's accumulator by clock E+60: the drain of hls::kSweepDrainCycles.
//
// Ports between lanes: the lane below writes this lane's ghost copy and reads its ghost
// sums; this lane reads the lane below's static words (its port B) for the ghosts'
// out-masks. Each lane counts the ghost particles it has read and whose sums it has
// written; the lane below checks every ghost write and ghost sum read against them and
// raises the schedule-conflict flag when it would come too early (the host's start delays
// prevent it). While the next step of a command has gone ahead (mixed_i), the lane below
// counts its ghost-copy writes and ghost-sum reads of the last step, and this lane checks
// its newer reads and writes against them (the host's period prevents a clash,
// host/driver/sweep_overlap.cpp).
//
// Steps overlap: slots of the next step may follow the last step's down this pipeline
// (docs/sweep_core.md). Everything counted at the TEM's output restarts at a step's first
// slot (a bit carried with it); what the MPM path counts restarts at step_end_i.
module rheo_sweep_lane #(
  parameter int W = 32,
  parameter int CoefW = 24,
  parameter int SlabDepth = 1024,
  parameter int GhostDepth = 256,
  parameter int Window = 512,
  parameter int HasGhost = 1,  // 0 for lane 0 (no lane below)
  parameter int DelayW = 24,
  localparam int SAW = $clog2(SlabDepth),
  localparam int GAW = $clog2(GhostDepth),
  localparam int Offsets = rheo_consts_pkg::SweepOffsets,
  localparam int OffW = rheo_consts_pkg::SweepOffsetBits,
  localparam int StatW = rheo_consts_pkg::SweepStaticBits,
  localparam int ClsW = rheo_consts_pkg::SweepClassBits,
  localparam int MassW = rheo_consts_pkg::SweepMassBits,
  localparam int SumW = rheo_consts_pkg::SweepSumBits,
  localparam int NW = rheo_consts_pkg::ZbtAddrBits,
  localparam int DW = rheo_consts_pkg::ZbtWordBits,
  localparam int NumCoef = rheo_consts_pkg::MaterialCoefs,
  localparam int MFlagsW = rheo_consts_pkg::MatFlagsW,
  localparam int MIdxW = 4,
  localparam int XpW = 6 * W
) (
  input  logic                    clk_i,
  input  logic                    rst_ni,
  input  logic                    go_i,         // a step starts (its plate word is taken)
  input  logic                    step_end_i,   // a step's force is latched: done restarts
  input  logic                    mixed_i,      // the next step went ahead of the last one's end
  input  logic                    idle_i,       // no step runs: the host owns the memories
  output logic                    done_o,       // every own particle of the step written
  input  logic [SAW:0]            count_i,
  input  logic [GAW:0]            ghost_i,
  input  logic [DelayW-1:0]       delay_i,
  input  logic [SAW:0]            prev_count_i,
  input  logic [GAW:0]            next_ghost_i,
  input  logic [Offsets*OffW-1:0] offsets_i,
  // The lane below's static words (its port B) and this lane's for the lane above.
  output logic [SAW-1:0]          prev_stat_addr_o,
  input  logic [StatW-1:0]        prev_stat_i,
  input  logic [SAW-1:0]          next_stat_addr_i,
  output logic [StatW-1:0]        next_stat_o,
  // This lane's ghost copy, written by the lane below's MPM or the host.
  input  logic                    gx_we_i,
  input  logic [GAW-1:0]          gx_addr_i,
  input  logic [XpW-1:0]          gx_wdata_i,
  // The lane above's ghost copy, written from this lane's MPM.
  output logic                    gxo_we_o,
  output logic [GAW-1:0]          gxo_addr_o,
  output logic [XpW-1:0]          gxo_wdata_o,
  // This lane's ghost sums, read by the lane below; the lane above's, read here.
  input  logic [GAW-1:0]          gs_raddr_i,
  output logic [3*SumW-1:0]       gs_rdata_o,
  output logic [GAW-1:0]          gsn_raddr_o,
  input  logic [3*SumW-1:0]       gsn_rdata_i,
  // Ghost particles read and ghost sums written so far this step (for the lane below),
  // and the lane above's.
  output logic [GAW:0]            xread_o,
  output logic [GAW:0]            xdone_o,
  input  logic [GAW:0]            next_xread_i,
  input  logic [GAW:0]            next_xdone_i,
  // Ghost copies written and ghost sums read by this lane's MPMs this step (for the lane
  // above, while two steps are in the lanes), and the lane below's.
  output logic [GAW:0]            gxw_o,
  output logic [GAW:0]            gsr_o,
  input  logic [GAW:0]            prev_gxw_i,
  input  logic [GAW:0]            prev_gsr_i,
  // Tables (rheo_sweep_tables, rheo_core_mem_mat): class -> L, material -> coefficients,
  // mass class -> 1/m, each one registered read.
  output logic [ClsW-1:0]         cls_o,        // E+4
  input  logic [W-1:0]            len_i,        // E+5
  input  logic [MIdxW-1:0]        cls_mat_i,    // E+5: the class's material
  output logic [MIdxW-1:0]        mat_o,        // to the material table, TemLateCoefClocks - 1 later
  input  logic [NumCoef*CoefW-1:0] coef_i,
  input  logic [MFlagsW-1:0]      mflags_i,
  output logic [MassW-1:0]        mass_o,
  input  logic [CoefW-1:0]        minv_i,
  // MPM globals.
  input  logic [3*W-1:0]          gravity_i,
  input  logic [W-1:0]            plate_z_i,
  input  logic                    plate_en_i,
  input  logic                    floor_en_i,
  input  logic                    hold_en_i,
  input  logic                    prev_valid_i,
  input  logic [W-1:0]            plate_prev_i,
  output logic                    plate_valid_o,
  output logic [W-1:0]            plate_f_o,
  output logic [31:0]             flags_o,      // status bits raised the clock before
  // Host access while idle.
  input  logic [SAW-1:0]          host_addr_i,
  input  logic                    host_xp_we_i,
  input  logic [XpW-1:0]          host_xp_wdata_i,
  output logic [XpW-1:0]          host_xp_rdata_o,
  input  logic                    host_stat_we_i,
  input  logic [StatW-1:0]        host_stat_wdata_i,
  output logic [StatW-1:0]        host_stat_rdata_o,
  input  logic                    host_zbt_valid_i,
  input  logic                    host_zbt_we_i,
  input  logic [NW:0]             host_zbt_addr_i,  // a slot: device (bit 0), address
  input  logic [DW-1:0]           host_zbt_wdata_i,
  output logic [DW-1:0]           host_zbt_rdata_o,
  // The two SRAM devices: {device 1, device 0}.
  output logic [2*NW-1:0]         zbt_a_o,
  output logic [1:0]              zbt_ce_n_o,
  output logic [1:0]              zbt_we_n_o,
  output logic [2*DW-1:0]         zbt_d_o,
  output logic [1:0]              zbt_d_oe_o,
  input  logic [2*DW-1:0]         zbt_q_i
);
  localparam int KW = $clog2(Offsets);
  localparam int WAW = $clog2(Window);
  localparam int TemLat = rheo_consts_pkg::TemLatency;
  localparam int AccW = SumW + 2;  // start + end + ghost sum
  localparam int QDepth = 32;      // own particles between their first slot and their MPM
  localparam int QAW = $clog2(QDepth);

  if (HasGhost == 0) begin : g_no_ghost_use
    logic unused;
    assign unused = ^{gx_we_i, gx_addr_i, gx_wdata_i, gs_raddr_i, prev_stat_i, prev_count_i};
  end

  // ---------------------------------------------------------------- stream
  logic s_slot, s_edge, s_first, s_last, s_cross, s_fixed, s_plate, s_has_in, s_has_cross;
  logic s_step_first, enum_busy;
  logic [SAW-1:0] s_idx;
  logic [KW-1:0] s_k;
  logic [NW:0] s_n;
  logic [MassW-1:0] s_mass;
  logic starved;
  logic [SAW-1:0] own_stat_addr;
  logic [StatW-1:0] own_stat;
  rheo_sweep_enum #(.SlabDepth(SlabDepth), .GhostDepth(GhostDepth), .DelayW(DelayW)) u_enum (
    .clk_i(clk_i), .rst_ni(rst_ni), .go_i(go_i), .count_i(count_i),
    .ghost_i(HasGhost != 0 ? ghost_i : '0), .prev_count_i(prev_count_i), .delay_i(delay_i),
    .offsets_i(offsets_i), .own_stat_addr_o(own_stat_addr), .own_stat_i(own_stat),
    .prev_stat_addr_o(prev_stat_addr_o), .prev_stat_i(prev_stat_i),
    .slot_o(s_slot), .edge_o(s_edge), .first_o(s_first), .last_o(s_last), .cross_o(s_cross),
    .idx_o(s_idx), .k_o(s_k), .n_o(s_n), .mass_o(s_mass), .fixed_o(s_fixed), .plate_o(s_plate),
    .has_in_o(s_has_in), .has_cross_o(s_has_cross), .step_first_o(s_step_first),
    .busy_o(enum_busy), .starved_o(starved));

  // ---------------------------------------------------------------- slot pipeline E+1..E+4
  // A slot's fields, carried along: {step_first, has_cross, has_in, plate, fixed, mass, n,
  // e, idx, cross, last, first, edge, slot}.
  localparam int PSlot = 0, PEdge = 1, PFirst = 2, PLast = 3, PCross = 4, PIdx = 5;
  localparam int PE = PIdx + SAW, PN = PE + SAW, PMass = PN + NW + 1, PFixed = PMass + MassW;
  localparam int PPlate = PFixed + 1, PHasIn = PPlate + 1, PHasCross = PHasIn + 1;
  localparam int PStepFirst = PHasCross + 1;
  localparam int PW = PStepFirst + 1;
  // E+1 holds the slot's offset o_k (PE), E+2 its end's local index there.
  logic [OffW-1:0] off_k;
  logic [SAW:0] e_own, e_cross;
  logic [PW-1:0] p1_q, p2_q, p3_q, p4_q;
  assign off_k = offsets_i[s_k*OffW +: OffW];
  assign e_own = {1'b0, p1_q[PIdx +: SAW]} + (SAW+1)'(p1_q[PE +: OffW]);
  // o_k - (ghost - a): in the slab whenever the enumerator put the edge in the stream.
  assign e_cross = (SAW+1)'(p1_q[PE +: OffW]) + {1'b0, p1_q[PIdx +: SAW]} - (SAW+1)'(ghost_i);
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      p1_q <= '0;
      p2_q <= '0;
      p3_q <= '0;
      p4_q <= '0;
    end else begin
      p1_q[PSlot] <= s_slot;
      p1_q[PEdge] <= s_edge;
      p1_q[PFirst] <= s_first;
      p1_q[PLast] <= s_last;
      p1_q[PCross] <= s_cross;
      p1_q[PIdx +: SAW] <= s_idx;
      p1_q[PE +: SAW] <= SAW'(off_k);
      p1_q[PN +: NW+1] <= s_n;
      p1_q[PMass +: MassW] <= s_mass;
      p1_q[PFixed] <= s_fixed;
      p1_q[PPlate] <= s_plate;
      p1_q[PHasIn] <= s_has_in;
      p1_q[PHasCross] <= s_has_cross;
      p1_q[PStepFirst] <= s_step_first;
      p2_q <= p1_q;
      p2_q[PE +: SAW] <= SAW'(p1_q[PCross] ? e_cross : e_own);
      p3_q <= p2_q;
      p4_q <= p3_q;
    end
  end

  // ---------------------------------------------------------------- memories
  // x/p of the slab: port A reads the end particles; port B reads a particle's start (its
  // first own slot), writes MPM results and serves the host.
  logic start_rd, ghost_rd;
  logic [XpW-1:0] xp_a, xp_b;
  logic xp_b_we;
  logic [SAW-1:0] xp_b_addr;
  logic [XpW-1:0] xp_b_wdata;
  logic wb_q;  // an MPM result waiting for port B
  logic [SAW-1:0] wb_addr_q;
  logic [XpW-1:0] wb_data_q;
  assign start_rd = p3_q[PSlot] && p3_q[PFirst] && !p3_q[PCross];
  assign ghost_rd = p3_q[PSlot] && p3_q[PFirst] && p3_q[PCross];
  always_comb begin
    if (idle_i) begin
      xp_b_we = host_xp_we_i;
      xp_b_addr = host_addr_i;
      xp_b_wdata = host_xp_wdata_i;
    end else begin
      xp_b_we = wb_q && !start_rd;
      xp_b_addr = start_rd ? p3_q[PIdx +: SAW] : wb_addr_q;
      xp_b_wdata = wb_data_q;
    end
  end
  rheo_ram_tdp #(.Width(XpW), .Depth(SlabDepth)) u_xp (
    .clk_i(clk_i), .a_addr_i(p3_q[PE +: SAW]), .a_data_o(xp_a),
    .b_we_i(xp_b_we), .b_addr_i(xp_b_addr), .b_data_i(xp_b_wdata), .b_data_o(xp_b));
  assign host_xp_rdata_o = xp_b;
  // Static words: port A feeds this lane's stream, port B the lane above's (its ghosts'
  // out-masks) and the host.
  logic [StatW-1:0] stat_b;
  rheo_ram_tdp #(.Width(StatW), .Depth(SlabDepth)) u_stat (
    .clk_i(clk_i), .a_addr_i(own_stat_addr), .a_data_o(own_stat),
    .b_we_i(idle_i && host_stat_we_i), .b_addr_i(idle_i ? host_addr_i : next_stat_addr_i),
    .b_data_i(host_stat_wdata_i), .b_data_o(stat_b));
  assign next_stat_o = stat_b;
  assign host_stat_rdata_o = stat_b;
  // The ghost copy and the MPM queue's x and p share a memory (block RAM): the ghost copy
  // at addresses 0 .. GhostDepth-1 (lanes with a lane below), the queue above it. Port A
  // reads the ghosts in the cross sweep and serves the queue in the own sweep (a write when
  // a particle's first slot has read it, a read for its MPM); port B takes the lane below's
  // (or the host's) ghost writes. The ghost sums have a memory of their own.
  localparam int QBase = (HasGhost != 0) ? GhostDepth : 0;
  localparam int GQDepth = QBase + QDepth;
  localparam int GQAW = $clog2(GQDepth);
  logic [XpW-1:0] ghost_xp;
  logic gq_we;
  logic [GQAW-1:0] gq_addr;
  logic [XpW-1:0] gq_wdata;
  rheo_ram_tdp2 #(.Width(XpW), .Depth(GQDepth)) u_ghost_queue (
    .clk_i(clk_i), .a_we_i(gq_we), .a_addr_i(gq_addr), .a_data_i(gq_wdata), .a_data_o(ghost_xp),
    .b_we_i(HasGhost != 0 && gx_we_i), .b_addr_i(GQAW'(gx_addr_i)), .b_data_i(gx_wdata_i));
  logic gs_we;
  logic [GAW-1:0] gs_waddr;
  logic [3*SumW-1:0] gs_wdata;
  if (HasGhost != 0) begin : g_ghost
    rheo_ram_sdp #(.Width(3 * SumW), .Depth(GhostDepth)) u_ghost_sum (
      .clk_i(clk_i), .a_addr_i(gs_raddr_i), .a_data_o(gs_rdata_o),
      .b_we_i(gs_we), .b_addr_i(gs_waddr), .b_data_i(gs_wdata));
  end else begin : g_no_ghost
    logic unused_gs;
    assign unused_gs = ^{gs_we, gs_waddr, gs_wdata};
    assign gs_rdata_o = '0;
  end

  // ---------------------------------------------------------------- SRAM
  // A slot's word lives in device n % 2 at n / 2 and is written back in place kResult
  // clocks after its read, an odd number: in any clock the slot read and the slot written
  // differ by that many slots, so they use different devices. The host reads and writes
  // any word while idle.
  localparam int ReadToWrite = rheo_consts_pkg::SweepSramClocks + 1 + TemLat;
  if (ReadToWrite % 2 != 1) begin : g_parity_check
    $error("rheo_sweep_lane: a slot's write must follow its read by an odd number of clocks");
  end
  logic rd_cmd, wr_cmd;
  logic [NW:0] wr_addr;
  logic [DW-1:0] wr_word;
  logic [DW-1:0] zbt_rdata [2];
  for (genvar b = 0; b < 2; b++) begin : g_zbt
    logic valid, we;
    logic [NW-1:0] addr;
    logic [DW-1:0] wdata;
    always_comb begin
      if (idle_i) begin
        valid = host_zbt_valid_i && host_zbt_addr_i[0] == 1'(b);
        we = host_zbt_we_i;
        addr = host_zbt_addr_i[NW:1];
        wdata = host_zbt_wdata_i;
      end else if (wr_cmd && wr_addr[0] == 1'(b)) begin
        valid = 1'b1;
        we = 1'b1;
        addr = wr_addr[NW:1];
        wdata = wr_word;
      end else begin
        valid = rd_cmd && s_n[0] == 1'(b);
        we = 1'b0;
        addr = s_n[NW:1];
        wdata = '0;
      end
    end
    rheo_zbt_port u_port (
      .clk_i(clk_i), .rst_ni(rst_ni), .cmd_valid_i(valid), .cmd_we_i(we), .cmd_addr_i(addr),
      .cmd_wdata_i(wdata), .rdata_o(zbt_rdata[b]),
      .zbt_a_o(zbt_a_o[b*NW +: NW]), .zbt_ce_n_o(zbt_ce_n_o[b]), .zbt_we_n_o(zbt_we_n_o[b]),
      .zbt_d_o(zbt_d_o[b*DW +: DW]), .zbt_d_oe_o(zbt_d_oe_o[b]), .zbt_q_i(zbt_q_i[b*DW +: DW]));
  end
  assign rd_cmd = s_slot && s_edge;
  // The word read four clocks ago: the slot's in E+4, the host's (its address held while
  // it waits) when idle.
  logic [DW-1:0] word4;
  assign word4 = zbt_rdata[idle_i ? host_zbt_addr_i[0] : p4_q[PN]];
  assign host_zbt_rdata_o = word4;

  // ---------------------------------------------------------------- operands E+4..E+6
  logic [XpW-1:0] xs4, xs_hold_q;
  assign xs4 = !p4_q[PFirst] ? xs_hold_q : (p4_q[PCross] ? ghost_xp : xp_b);
  assign cls_o = word4[W +: ClsW];
  logic [PW-1:0] p5_q;
  logic [XpW-1:0] xs5_q, xe5_q;
  logic [W-1:0] d5_q;
  logic [ClsW-1:0] cls5_q;
  logic fin5_q;  // the edge is the first into its end
  always_ff @(posedge clk_i) begin
    if (p4_q[PSlot] && p4_q[PFirst]) xs_hold_q <= xs4;
    xs5_q <= xs4;
    xe5_q <= xp_a;
    d5_q <= word4[W-1:0];
    cls5_q <= word4[W +: ClsW];
    fin5_q <= word4[W + ClsW];
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) p5_q <= '0;
    else p5_q <= p4_q;
  end

  // ---------------------------------------------------------------- TEM
  // The TEM takes the edge in E+5 (L from the class table with it) and its material's
  // coefficients TemLateCoefClocks later, when its products need them: the material index
  // (from the class table in E+5) waits here, four bits wide, instead of the six
  // coefficients inside the TEM.
  localparam int LateCoef = rheo_consts_pkg::TemLateCoefClocks;
  rheo_delay #(.W(MIdxW), .N(LateCoef - 1)) u_mat_wait (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(cls_mat_i), .q_o(mat_o));
  logic tem_valid, tem_sat, tem_degen;
  logic [3*W-1:0] tem_f;
  logic [W-1:0] tem_d;
  logic unused_tem;
  logic [0:0] tem_idx;
  logic [W-1:0] tem_m;
  rheo_tem #(.W(W), .CoefW(CoefW), .IdxW(1), .LateCoef(1)) u_tem (
    .clk_i(clk_i), .rst_ni(rst_ni), .valid_i(p5_q[PSlot] && p5_q[PEdge]), .idx_i(1'b0),
    .xs_i(xs5_q[0 +: 3*W]), .xe_i(xe5_q[0 +: 3*W]), .ps_i(xs5_q[3*W +: 3*W]),
    .pe_i(xe5_q[3*W +: 3*W]), .d_i(d5_q), .len_i(len_i), .m_i('0), .coef_i(coef_i),
    .mat_flags_i(mflags_i), .valid_o(tem_valid), .idx_o(tem_idx), .f_o(tem_f), .d_o(tem_d),
    .m_o(tem_m), .sat_o(tem_sat), .degenerate_o(tem_degen));
  assign unused_tem = ^{tem_idx, tem_m};
  // What the results need of the slot waits beside the TEM (padding slots too): its flags,
  // the end's window address, the class and first tag. The SRAM word and the particle
  // are counted again at the output (they come in stream order), from 0 at a step's first
  // slot: the next step's slots may follow the last one's into the TEM.
  localparam int UW = 6 + WAW + ClsW + 1;
  logic [UW-1:0] u_in, u_out;
  logic u_slot, u_edge_bit, u_first, u_last, u_cross, u_fin, u_step_first;
  logic [WAW-1:0] u_e;
  logic [ClsW-1:0] u_cls;
  assign u_in = {p5_q[PStepFirst], fin5_q, cls5_q, p5_q[PE +: WAW], p5_q[PCross], p5_q[PLast],
                 p5_q[PFirst], p5_q[PEdge], p5_q[PSlot]};
  rheo_delay #(.W(UW), .N(TemLat)) u_beside_tem (
    .clk_i(clk_i), .rst_ni(rst_ni), .d_i(u_in), .q_o(u_out));
  assign {u_step_first, u_fin, u_cls, u_e, u_cross, u_last, u_first, u_edge_bit, u_slot} = u_out;
  logic u_edge;
  assign u_edge = u_slot && u_edge_bit;
  // The slot's number (its SRAM word) and particle, counted at the output: slots leave the
  // TEM in the order they entered it.
  logic [NW:0] wr_n_q, wr_n;
  logic [SAW-1:0] u_cross_idx_q, u_own_idx_q, u_cross_idx, u_own_idx;
  logic u_restart;
  assign u_restart = u_slot && u_step_first;
  assign wr_n = u_restart ? '0 : wr_n_q;
  assign u_cross_idx = u_restart ? '0 : u_cross_idx_q;
  assign u_own_idx = u_restart ? '0 : u_own_idx_q;

  // ---------------------------------------------------------------- E+45: results
  assign wr_cmd = u_edge;
  assign wr_addr = wr_n;
  assign wr_word = {u_fin, u_cls, tem_d};
  logic signed [SumW-1:0] f_ext [3];
  logic [3*SumW-1:0] neg_f;
  for (genvar i = 0; i < 3; i++) begin : g_f
    assign f_ext[i] = SumW'($signed(tem_f[i*W +: W]));
    assign neg_f[i*SumW +: SumW] = -f_ext[i];
  end
  logic [WAW-1:0] sum_raddr;
  logic [3*SumW-1:0] end_sum;
  rheo_sweep_end_sums #(.SumW(SumW), .Depth(Window)) u_end_sums (
    .clk_i(clk_i), .rst_ni(rst_ni), .add_valid_i(u_edge), .add_first_i(u_fin),
    .add_addr_i(u_e), .add_val_i(neg_f), .sum_addr_i(sum_raddr), .sum_o(end_sum));
  // The particle's start sum.
  logic [3*SumW-1:0] sacc_q;
  logic g1_q, g1_cross_q;
  logic [SAW-1:0] g1_idx_q;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++)
      sacc_q[i*SumW +: SumW] <= (u_first ? SumW'(0) : sacc_q[i*SumW +: SumW]) +
                                (u_edge ? f_ext[i] : SumW'(0));
    g1_cross_q <= u_cross;
    g1_idx_q <= u_cross ? u_cross_idx : u_own_idx;
  end

  // ---------------------------------------------------------------- E+46: a particle is done
  // Cross: its start sum to the ghost sums. Own: read its end sum, the lane above's ghost
  // sum and its queued static fields.
  logic own_end, cross_end;
  assign own_end = g1_q && !g1_cross_q;
  assign cross_end = g1_q && g1_cross_q;
  assign gs_we = cross_end;
  assign gs_waddr = GAW'(g1_idx_q);
  assign gs_wdata = sacc_q;
  assign sum_raddr = g1_idx_q[WAW-1:0];
  // The lane above's ghosts are this slab's last next_ghost particles.
  // From registers: count_i and next_ghost_i are the lane registers the host writes
  // between steps, many clocks before the next one starts.
  logic [SAW:0] ghost_from;
  logic has_next_ghost;
  always_ff @(posedge clk_i) begin
    ghost_from <= count_i - (SAW+1)'(next_ghost_i);
    has_next_ghost <= next_ghost_i != '0;
  end
  assign gsn_raddr_o = GAW'(g1_idx_q - SAW'(ghost_from));

  logic m2_q, m3_q, m4_q, m5_q;  // a particle's force sums, saturation, MPM input
  // The MPM queue: an own particle's static fields (LUT RAM, read in E+46) and its x and p
  // (the ghost memory's upper part), from its first slot to its MPM. The x/p entries are
  // read ahead into two head registers whenever port A has nothing else to do, and the MPM
  // takes the first in E+50: the MPM's clock never needs the port, which a next step's ghost
  // reads could hold (host/driver/sweep_overlap.cpp, docs/synthesis.md §8). An entry's
  // write waits a clock when a ghost read has the port.
  localparam int SW = MassW + 4;
  (* ram_style = "distributed" *) logic [SW-1:0] qs_mem [QDepth];
  logic [QAW-1:0] q_wr_q, qs_wr_q, qs_rd_q, qx_rd_q;  // qx_rd_q: the next entry to read ahead
  logic [QAW:0] q_cnt_q;
  logic q_push, qx_pend_q;
  logic [XpW-1:0] qx_pend_data_q;
  logic [SW-1:0] qs_head;
  assign q_push = p4_q[PSlot] && p4_q[PFirst] && !p4_q[PCross];
  assign qs_head = qs_mem[qs_rd_q];
  always_ff @(posedge clk_i) begin
    if (q_push)
      qs_mem[qs_wr_q] <= {p4_q[PHasCross], p4_q[PHasIn], p4_q[PPlate], p4_q[PFixed],
                          p4_q[PMass +: MassW]};
  end
  // Port A: a ghost read (cross sweep), else a waiting x/p write, else a read ahead into
  // the head registers when an entry is in memory and a register will be free.
  logic q_write, q_fetch, fetch_q, q_take;
  logic [1:0] h_cnt_q;              // head registers holding an entry
  logic [XpW-1:0] h0_q, h1_q;
  assign q_take = m5_q;             // the MPM's input takes the first head register
  always_comb begin
    q_write = 1'b0;
    q_fetch = 1'b0;
    gq_wdata = qx_pend_data_q;
    if (ghost_rd) begin
      gq_addr = GQAW'(p3_q[PIdx +: SAW]);
    end else if (qx_pend_q) begin
      gq_addr = GQAW'(QBase) + GQAW'(q_wr_q);
      q_write = 1'b1;
    end else begin
      gq_addr = GQAW'(QBase) + GQAW'(qx_rd_q);
      q_fetch = qx_rd_q != q_wr_q && 3'(h_cnt_q) + 3'(fetch_q) <= 3'd1 + 3'(q_take);
    end
    gq_we = q_write;
  end
  // The head registers: an entry read ahead arrives a clock after its read (fetch_q) and
  // goes behind those the MPM has not taken.
  logic [1:0] h_kept;
  assign h_kept = h_cnt_q - 2'(q_take);
  always_ff @(posedge clk_i) begin
    if (q_take) h0_q <= h1_q;
    if (fetch_q) begin
      if (h_kept == 2'd0) h0_q <= ghost_xp;
      else h1_q <= ghost_xp;
    end
  end
  logic h_has_cross, h_has_in;
  assign mass_o = qs_head[0 +: MassW];
  assign h_has_in = qs_head[MassW + 2];
  assign h_has_cross = qs_head[MassW + 3];

  // E+47..E+50: the particle's force: start + end sum (E+47, from the window's registered
  // output), + the lane above's ghost sum (E+48), saturated to a word (E+49), so that no
  // clock holds a block RAM's clock-to-out and two 38-bit additions in a row.
  logic [3*SumW-1:0] m2_sacc_q;
  logic m2_has_in_q, m2_has_cross_q, m2_ghost_ok_q;
  logic [1:0] m2_flags_q, m3_flags_q, m4_flags_q, m5_flags_q;  // {plate, fixed}
  logic [SAW-1:0] m2_idx_q, m3_idx_q, m4_idx_q, m5_idx_q;
  logic [CoefW-1:0] m3_minv_q, m4_minv_q, m5_minv_q;
  logic signed [AccW-1:0] m3_part_q [3], m3_ghost_q [3], m4_f_q [3];
  logic [3*W-1:0] m5_f_q;
  logic m5_sat_q;
  always_ff @(posedge clk_i) begin
    m2_sacc_q <= sacc_q;
    m2_flags_q <= qs_head[MassW +: 2];
    m2_idx_q <= g1_idx_q;
    m2_has_in_q <= h_has_in;
    m2_has_cross_q <= h_has_cross;
    m2_ghost_ok_q <= {1'b0, g1_idx_q} >= ghost_from && has_next_ghost;
    for (int i = 0; i < 3; i++) begin
      m3_part_q[i] <= AccW'($signed(m2_sacc_q[i*SumW +: SumW])) +
                      (m2_has_in_q ? AccW'($signed(end_sum[i*SumW +: SumW])) : AccW'(0));
      m3_ghost_q[i] <= m2_has_cross_q && m2_ghost_ok_q
                           ? AccW'($signed(gsn_rdata_i[i*SumW +: SumW])) : AccW'(0);
      m4_f_q[i] <= m3_part_q[i] + m3_ghost_q[i];
    end
    m3_flags_q <= m2_flags_q;
    m3_idx_q <= m2_idx_q;
    m3_minv_q <= minv_i;
    m4_flags_q <= m3_flags_q;
    m4_idx_q <= m3_idx_q;
    m4_minv_q <= m3_minv_q;
    m5_sat_q <= 1'b0;
    for (int i = 0; i < 3; i++) begin
      if (m4_f_q[i] > AccW'(2**(W-1) - 1)) begin
        m5_f_q[i*W +: W] <= {1'b0, {(W-1){1'b1}}};
        m5_sat_q <= 1'b1;
      end else if (m4_f_q[i] < -AccW'(2**(W-1))) begin
        m5_f_q[i*W +: W] <= {1'b1, {(W-1){1'b0}}};
        m5_sat_q <= 1'b1;
      end else begin
        m5_f_q[i*W +: W] <= m4_f_q[i][W-1:0];
      end
    end
    m5_flags_q <= m4_flags_q;
    m5_idx_q <= m4_idx_q;
    m5_minv_q <= m4_minv_q;
  end

  // ---------------------------------------------------------------- MPM
  logic mpm_valid, mpm_sat;
  logic [SAW-1:0] mpm_idx;
  logic [3*W-1:0] mpm_x, mpm_p;
  logic [XpW-1:0] qx_head;
  assign qx_head = h0_q;
  rheo_mpm #(.W(W), .CoefW(CoefW), .IdxW(SAW)) u_mpm (
    .clk_i(clk_i), .rst_ni(rst_ni), .valid_i(m5_q), .idx_i(m5_idx_q), .f_i(m5_f_q),
    .x_i(qx_head[0 +: 3*W]), .p_i(qx_head[3*W +: 3*W]), .x0_i(qx_head[0 +: 3*W]),
    .minv_i(m5_minv_q), .flags_i(m5_flags_q),
    .g_i(gravity_i), .plate_z_i(plate_z_i), .plate_en_i(plate_en_i), .floor_en_i(floor_en_i),
    .hold_en_i(hold_en_i), .prev_valid_i(prev_valid_i), .plate_prev_i(plate_prev_i),
    .valid_o(mpm_valid), .idx_o(mpm_idx),
    .x_o(mpm_x), .p_o(mpm_p), .plate_f_o(plate_f_o), .sat_o(mpm_sat));
  assign plate_valid_o = mpm_valid;
  // To the lane above's ghost copy.
  assign gxo_we_o = mpm_valid && {1'b0, mpm_idx} >= ghost_from && has_next_ghost;
  assign gxo_addr_o = GAW'(mpm_idx - SAW'(ghost_from));
  assign gxo_wdata_o = {mpm_p, mpm_x};

  // ---------------------------------------------------------------- control and checks
  logic [SAW:0] written_q, ended_q, wb_done_q;
  logic [GAW:0] xread_q, xdone_q, gxw_q, gsr_q;
  logic newer_q, newer_rd_q, newer_rd, newer_out_q, g1_restart_q, wb_write, gs_read, p3_restart;
  // A ghost-copy write and a ghost-sum read are counted a clock after they happen (their
  // decisions end in compares; the count's adder is then a clock of its own): the lane
  // above's checks see them a clock late, which host/driver/sweep_overlap.cpp allows for.
  logic gxw_count_q, gsr_count_q;
  assign p3_restart = p3_q[PSlot] && p3_q[PStepFirst];
  assign newer_rd = newer_rd_q || (p3_restart && newer_q);
  assign wb_write = !idle_i && wb_q && !start_rd;
  assign gs_read = own_end && h_has_cross && {1'b0, g1_idx_q} >= ghost_from && has_next_ghost;
  logic conflict;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      g1_q <= 1'b0;
      m2_q <= 1'b0;
      m3_q <= 1'b0;
      m4_q <= 1'b0;
      m5_q <= 1'b0;
      wb_q <= 1'b0;
      wb_addr_q <= '0;
      wb_data_q <= '0;
      q_wr_q <= '0;
      qs_wr_q <= '0;
      qs_rd_q <= '0;
      qx_rd_q <= '0;
      fetch_q <= 1'b0;
      h_cnt_q <= '0;
      qx_pend_q <= 1'b0;
      qx_pend_data_q <= '0;
      q_cnt_q <= '0;
      wr_n_q <= '0;
      u_cross_idx_q <= '0;
      u_own_idx_q <= '0;
      written_q <= '0;
      ended_q <= '0;
      wb_done_q <= '0;
      done_o <= 1'b1;
      xread_q <= '0;
      xdone_q <= '0;
      gxw_q <= '0;
      gsr_q <= '0;
      newer_q <= 1'b0;
      gxw_count_q <= 1'b0;
      gsr_count_q <= 1'b0;
      newer_rd_q <= 1'b0;
      newer_out_q <= 1'b0;
      g1_restart_q <= 1'b0;
    end else begin
      g1_q <= u_slot && u_last;
      g1_restart_q <= u_restart;
      gxw_count_q <= gxo_we_o && !step_end_i;
      gsr_count_q <= gs_read && !step_end_i;
      m2_q <= own_end;
      m3_q <= m2_q;
      m4_q <= m3_q;
      m5_q <= m4_q;
      if (q_push) qs_wr_q <= qs_wr_q + 1'b1;
      if (own_end) qs_rd_q <= qs_rd_q + 1'b1;
      if (q_fetch) qx_rd_q <= qx_rd_q + 1'b1;
      fetch_q <= q_fetch;
      h_cnt_q <= h_kept + 2'(fetch_q);
      // The x/p entry waits in qx_pend until port A takes it.
      if (q_write) q_wr_q <= q_wr_q + 1'b1;
      if (q_push) begin
        qx_pend_q <= 1'b1;
        qx_pend_data_q <= xp_b;
      end else if (q_write) begin
        qx_pend_q <= 1'b0;
      end
      q_cnt_q <= q_cnt_q + (QAW+1)'(q_push) - (QAW+1)'(q_take);
      if (u_slot) begin
        wr_n_q <= wr_n + 1'b1;
        u_cross_idx_q <= u_cross_idx + SAW'(u_last && u_cross);
        u_own_idx_q <= u_own_idx + SAW'(u_last && !u_cross);
      end
      // An MPM result waits in wb for port B (a start read has it in that clock).
      if (mpm_valid) begin
        wb_q <= 1'b1;
        wb_addr_q <= mpm_idx;
        wb_data_q <= {mpm_p, mpm_x};
      end else if (wb_q && !start_rd) begin
        wb_q <= 1'b0;
      end
      // Particles of the step on their MPM path (sums complete, results, results written
      // back): from 0 at the step's end, after which the next step's may begin
      // (host/driver/sweep_overlap.cpp puts them there).
      if (step_end_i) begin
        ended_q <= '0;
        written_q <= '0;
        wb_done_q <= '0;
        done_o <= count_i == '0;
        gxw_q <= '0;
        gsr_q <= '0;
      end else begin
        ended_q <= ended_q + (SAW+1)'(own_end);
        written_q <= written_q + (SAW+1)'(mpm_valid);
        wb_done_q <= wb_done_q + (SAW+1)'(wb_write);
        done_o <= (written_q + (SAW+1)'(mpm_valid)) == count_i;
        gxw_q <= gxw_q + (GAW+1)'(gxw_count_q);
        gsr_q <= gsr_q + (GAW+1)'(gsr_count_q);
      end
      // Ghosts read and ghost sums written, from the step's first slot (at the reads, at
      // the TEM's output): the last step's slots may still be on their way after a go.
      xread_q <= (p3_restart ? '0 : xread_q) + (GAW+1)'(ghost_rd);
      xdone_q <= (g1_restart_q ? '0 : xdone_q) + (GAW+1)'(cross_end);
      // A step gone ahead of the last one's end (newer_q, from its go): its slots at the
      // reads (newer_rd_q) and at the TEM's output (newer_out_q), from its first slot there.
      if (step_end_i) begin
        newer_q <= 1'b0;
        newer_rd_q <= 1'b0;
        newer_out_q <= 1'b0;
      end else begin
        if (go_i && mixed_i) newer_q <= 1'b1;
        if (p3_restart && newer_q) newer_rd_q <= 1'b1;
        if (u_restart && newer_q) newer_out_q <= 1'b1;
      end
    end
  end
  // While a step has gone ahead, the lane below's MPMs finish the last one, whose ghosts
  // this lane has all read and whose sums it has all written: its counts say so.
  assign xread_o = newer_rd_q ? '1 : xread_q;
  assign xdone_o = newer_out_q ? '1 : xdone_q;
  assign gxw_o = gxw_q;
  assign gsr_o = gsr_q;
  // Hazards the host's start delays and period keep apart (host/driver/sweep_overlap.cpp);
  // the flag reports a load or period that does not:
  //   one step: a ghost sum read before the lane above wrote it, a ghost write before it
  //   read the ghost;
  //   a step gone ahead (newer_*): a read of a particle's x/p before the last step wrote it
  //   back, a ghost read before the lane below wrote that ghost, a ghost sum written before
  //   the lane below read the last one, an end-side addition into a window entry the last
  //   step's MPM has not read, a particle's MPM path (its sums read) before the last step's
  //   end;
  //   a go while the stream still runs, a full queue, an entry not read ahead in time, two
  //   write-backs for port B, a starved stream.
  // Its terms are registered and raise the flag a clock later (the status is read long
  // after a step ends), so the comparisons do not meet the flag logic in one clock.
  // The last step's last particle in the addition's window entry (local index = u_e mod
  // Window), if it has one.
  logic [SAW:0] need_e;
  logic e_used;
  if (SAW + 1 > WAW) begin : g_window_alias
    assign e_used = count_i > (SAW+1)'(u_e);
    assign need_e = {(SAW+1-WAW)'((count_i - 1'b1 - (SAW+1)'(u_e)) >> WAW), u_e};
  end else begin : g_window_whole  // a window as deep as the slab: one particle per entry
    logic unused_e_hi;
    if (WAW > SAW) begin : g_hi
      assign unused_e_hi = ^u_e[WAW-1:SAW];
    end else begin : g_no_hi
      assign unused_e_hi = 1'b0;
    end
    assign e_used = 1'b1;
    assign need_e = {1'b0, u_e[SAW-1:0]};
  end
  logic [12:0] conflict_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) conflict_q <= '0;
    else conflict_q <= {own_end && h_has_cross &&
                          !({1'b0, g1_idx_q} >= ghost_from && has_next_ghost &&
                            {1'b0, gsn_raddr_o} < next_xdone_i),
                        gxo_we_o && !({1'b0, gxo_addr_o} < next_xread_i),
                        newer_rd && p3_q[PSlot] && p3_q[PEdge] &&
                          !({1'b0, p3_q[PE +: SAW]} < wb_done_q),
                        newer_rd && start_rd && !({1'b0, p3_q[PIdx +: SAW]} < wb_done_q),
                        newer_rd && ghost_rd && !({1'b0, p3_q[PIdx +: SAW]} < {{(SAW-GAW){1'b0}}, prev_gxw_i}),
                        newer_out_q && cross_end && !({1'b0, g1_idx_q} < {{(SAW-GAW){1'b0}}, prev_gsr_i}),
                        (newer_out_q || (u_restart && newer_q)) && u_edge && e_used && !(need_e < written_q),
                        own_end && ended_q == count_i,
                        go_i && enum_busy,
                        starved,
                        q_push && q_cnt_q == (QAW+1)'(QDepth),
                        q_take && h_cnt_q == '0,
                        mpm_valid && wb_q && start_rd};
  end
  assign conflict = |conflict_q;
  // Raised a clock later (registered): the status is read long after a step ends.
  logic [31:0] flags;
  always_comb begin
    flags = '0;
    if (tem_valid && tem_sat) flags |= 32'(rheo_consts_pkg::StatusTemSat);
    if (tem_valid && tem_degen) flags |= 32'(rheo_consts_pkg::StatusDegenerate);
    if ((mpm_valid && mpm_sat) || (m5_q && m5_sat_q)) flags |= 32'(rheo_consts_pkg::StatusMpmSat);
    if (conflict) flags |= 32'(rheo_consts_pkg::StatusScheduleConflict);
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) flags_o <= '0;
    else flags_o <= flags;
  end

`ifndef SYNTHESIS
  // The queue never overflows (at most (TemLatency + 11) / SweepOwnMinSlots particles wait)
  // and an MPM result never finds the previous one still waiting for port B.
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
    end else begin
      assert (!(q_push && q_cnt_q == (QAW+1)'(QDepth))) else $error("rheo_sweep_lane: MPM queue overflow");
      assert (!(q_take && h_cnt_q == '0))
        else $error("rheo_sweep_lane: the MPM's queue entry not read ahead in time");
      assert (!(q_push && qx_pend_q && !q_write))
        else $error("rheo_sweep_lane: an x/p entry still waiting for port A");
      assert (!(ghost_rd && qx_pend_q))
        else $error("rheo_sweep_lane: a queue entry waiting for port A during the cross sweep");
      assert (!(mpm_valid && wb_q && start_rd)) else $error("rheo_sweep_lane: two MPM results for port B");
      assert (!starved) else $error("rheo_sweep_lane: the stream starved (prefetch behind)");
      if (conflict_q != '0) $display("rheo_sweep_lane: schedule conflict terms %b at %0t", conflict_q, $time);
      assert (idle_i || !(rd_cmd && wr_cmd && s_n[0] == wr_addr[0]))
        else $error("rheo_sweep_lane: a slot's read and another's write in one SRAM device");
    end
  end
`endif
endmodule
