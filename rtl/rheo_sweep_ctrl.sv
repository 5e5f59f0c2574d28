// Command controller of the sweep core (rtl/rheo_sweep_core.sv): decodes the command
// stream (hls/frame_format.hpp), owns the control registers (lane registers, globals,
// status, the output word) and sequences a step. The same two-process form as
// rheo_core_ctrl: the always_comb block computes every register's next value (*_d), one
// always_ff registers them (*_q).
//
// Addressing: a particle's global index (regions ParticleState and SweepParticle) is found
// in the lane whose slab holds it (a compare against every lane's first particle when a
// command starts, then local + 1 and the next lane at a slab's end); a sweep slot index
// (regions SweepEdge and EdgeLength) is lane << SweepSlotLaneShift | n. An index outside
// every slab raises the bad-command flag.
// A write of a particle's state goes to its slab and, when the lane above keeps a ghost
// copy of it, to that copy too (the six words are gathered first: the memories take an
// entry in one write).
//
// A step: the plate word is taken in clock 0 (go); the lanes sweep; when every lane has
// written its last particle (done) the plate force is complete one clock later and is
// sent. The compute clocks of a step (status word 2) count from the plate word's clock to
// the clock before the force word is offered: max over lanes of (start delay + slots) +
// SweepDrainCycles (hls::sweep_cycles).
//
// Steps of one command overlap: the next step's plate word is taken ahead while a step
// runs, and when the host's period (global SweepPeriod, host/driver/sweep_overlap.hpp: the
// least start-to-start clocks at which no memory word or port of two steps meets) has
// passed since the last go, the next step goes (ahead) while the last one drains. Its
// plate word reaches the MPMs at the last step's end (step_end_o: the force is latched, the
// plate sum cleared, the lanes' done counts restart), which the period puts before its
// first MPM. Exactly at the period or not at all: a step that misses it (its word not there,
// the force word not yet sent) starts after the last one's force, as without a period, so
// that no other start-to-start distance is ever run. A command of n steps takes
// (n - 1) x period + one step's clocks (hls::sweep_command_cycles).
module rheo_sweep_ctrl #(
  parameter int Lanes = 5,
  parameter int SlabDepth = 1024,
  parameter int GhostDepth = 256,
  parameter int W = 32,
  parameter int DelayW = 24,
  localparam int SAW = $clog2(SlabDepth),
  localparam int GAW = $clog2(GhostDepth),
  localparam int LW = (Lanes > 1) ? $clog2(Lanes) : 1,
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW,
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW,
  localparam int NW = rheo_consts_pkg::ZbtAddrBits,
  localparam int DW = rheo_consts_pkg::ZbtWordBits
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  input  logic [W-1:0] s_axis_tdata,
  input  logic         s_axis_tvalid,
  output logic         s_axis_tready,
  input  logic         s_axis_tlast,
  output logic [W-1:0] m_axis_tdata,
  output logic         m_axis_tvalid,
  input  logic         m_axis_tready,
  output logic         m_axis_tlast,
  output logic         busy_o,
  // Host access: the entry's region, index, lane and local address, its words.
  output logic                   host_we_o,      // a word of a table or global entry
  output logic [RegionW-1:0]     region_o,
  output logic [FieldW-1:0]      field_o,
  output logic [IdxCountW-1:0]   index_o,
  output logic [W-1:0]           wdata_o,
  output logic [LW-1:0]          lane_o,         // the entry's lane
  output logic [SAW-1:0]         local_o,        // its local address in the slab
  output logic                   xp_we_o,        // write the gathered state entry
  output logic                   stat_we_o,      // write a static word (wdata_o)
  output logic [6*W-1:0]         xp_wdata_o,
  output logic                   ghost_we_o,     // and the lane above's ghost copy
  output logic [GAW-1:0]         ghost_addr_o,
  output logic                   zbt_valid_o,    // an SRAM command of the host
  output logic                   zbt_we_o,
  output logic [NW:0]            zbt_addr_o,     // the slot: its device (bit 0), address
  output logic [DW-1:0]          zbt_wdata_o,
  input  logic [W-1:0]           read_word_i,    // the entry's word (read-back mux)
  // Step.
  output logic                   idle_o,
  output logic                   go_o,
  output logic                   step_end_o,     // a step's force latched: the MPMs take the next
  output logic                   mixed_o,        // two steps in the lanes (go ahead .. step_end)
  output logic                   acc_clear_o,    // the plate sum starts afresh
  input  logic [Lanes-1:0]       done_i,
  output logic [Lanes*(SAW+1)-1:0] count_o,
  output logic [Lanes*(GAW+1)-1:0] ghost_o,
  output logic [Lanes*DelayW-1:0]  delay_o,
  output logic [3*W-1:0]         gravity_o,
  output logic                   floor_en_o,
  output logic                   plate_en_o,
  output logic [W-1:0]           plate_z_o,
  output logic                   hold_en_o,
  output logic                   prev_valid_o,
  output logic [W-1:0]           plate_prev_o,
  input  logic [31:0]            lane_flags_i,
  input  logic [PlateAccW-1:0]   plate_acc_i
);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int OpW = rheo_consts_pkg::HeaderOpcodeBits;
  localparam int ReadWait = 1 + rheo_consts_pkg::ZbtLatency + 1;  // an SRAM word's clocks
  // A fetch waits ReadWait + 1 clocks for an SRAM word: the read-back takes two registered
  // steps (the lane's field, then the lane; rheo_sweep_core).
  localparam int FetchWait = ReadWait + 1;
  localparam int WaitW = $clog2(FetchWait + 1);

  typedef enum logic [3:0] {
    StIdle, StWStart, StWLocate, StWData, StRStart, StRLocate, StRFetch, StRLoad, StRSend,
    StStatFetch, StStatSend, StRunPlate, StRun, StDrain, StForceOut
  } state_e;

  state_e state_q, state_d;
  logic reading_q, reading_d;
  logic [RegionW-1:0] region_q, region_d;
  logic [FieldW-1:0] last_field_q, last_field_d, field_q, field_d;
  logic [IdxCountW-1:0] count_q, count_d, index_q, index_d;
  logic [LW-1:0] lane_q, lane_d;
  logic [SAW:0] local_q, local_d;
  logic in_slab_q, in_slab_d;       // the particle entry lies in a slab
  logic [WaitW-1:0] wait_q, wait_d;
  logic clear_q, clear_d;
  logic [W-1:0] out_data_q, out_data_d;
  logic out_valid_q, out_valid_d, out_last_q, out_last_d;
  logic [5*W-1:0] xp_buf_q, xp_buf_d;  // the first five words of a state entry
  logic [IdxCountW-1:0] first_q [Lanes], first_d [Lanes];
  logic [SAW:0] lcount_q [Lanes], lcount_d [Lanes];
  logic [GAW:0] lghost_q [Lanes], lghost_d [Lanes];
  logic [DelayW-1:0] ldelay_q [Lanes], ldelay_d [Lanes];
  logic [3*W-1:0] gravity_q, gravity_d;
  logic floor_en_q, floor_en_d, plate_en_q, plate_en_d;
  logic [W-1:0] plate_z_q, plate_z_d;
  logic plate_hold_en_q, plate_hold_en_d, plate_prev_valid_q, plate_prev_valid_d;
  logic [W-1:0] plate_prev_q, plate_prev_d;
  logic [31:0] status_q, status_d, step_count_q, step_count_d, cycle_count_q, cycle_count_d;
  // Overlapped steps: the period, clocks since the last go, the next plate word taken ahead
  // (next_*), the step gone ahead and its plate word (ahead_*), two steps in the lanes.
  localparam int PeriodW = IdxCountW;
  // The period is kept as period - 1 (compared with the clocks since the last go) and
  // whether it is set.
  logic [PeriodW-1:0] period_m1_q, period_m1_d, since_go_q, since_go_d;
  logic [IdxCountW-1:0] words_left_q, words_left_d;  // the run command's words not yet taken
  logic next_valid_q, next_valid_d, ahead_q, ahead_d, mixed_q, mixed_d;
  logic [W-1:0] next_word_q, next_word_d, ahead_word_q, ahead_word_d;
  logic take_next, go_ahead, step_end;
  // Registered, so that no count compare sits before the input's ready or the lanes' go:
  // the command has words left to take; a period is set; this clock is the period after the
  // last go (once per go: the counter wraps after 2^24 clocks).
  logic more_q, more_d, period_nz_q, period_nz_d, at_period_q, at_period_d, passed_q, passed_d;
  logic word_taken;

  logic [OpW-1:0] hdr_opcode;
  logic [RegionW-1:0] hdr_region;
  logic [IdxCountW-1:0] hdr_count, word_index;
  assign hdr_opcode = s_axis_tdata[rheo_consts_pkg::HeaderOpcodeShift +: OpW];
  assign hdr_region = s_axis_tdata[rheo_consts_pkg::HeaderRegionShift +: RegionW];
  assign hdr_count = s_axis_tdata[rheo_consts_pkg::HeaderCountShift +: IdxCountW];
  assign word_index = s_axis_tdata[IdxCountW-1:0];

  logic in_fire, out_fire;
  // The next plate word of a run command is taken while a step runs.
  assign take_next = (state_q == StRun || state_q == StDrain || state_q == StForceOut) &&
                     !next_valid_q && more_q;
  assign s_axis_tready = (state_q == StIdle) || (state_q == StWStart) || (state_q == StWData) ||
                         (state_q == StRStart) || (state_q == StRunPlate && !next_valid_q) ||
                         take_next;
  assign in_fire = s_axis_tvalid && s_axis_tready;
  assign out_fire = out_valid_q && m_axis_tready;
  assign m_axis_tdata = out_data_q;
  assign m_axis_tvalid = out_valid_q;
  assign m_axis_tlast = out_last_q;
  assign busy_o = (state_q == StRun) || (state_q == StDrain) || ahead_q;
  assign idle_o = !busy_o;

  // Which regions a command may name, and how their entries are addressed.
  function automatic logic region_ok(input logic [RegionW-1:0] r);
    region_ok = r == RegionW'(rheo_consts_pkg::RegionGlobals) ||
                r == RegionW'(rheo_consts_pkg::RegionParticleState) ||
                r == RegionW'(rheo_consts_pkg::RegionMaterial) ||
                r == RegionW'(rheo_consts_pkg::RegionEdgeLength) ||
                (r >= RegionW'(rheo_consts_pkg::RegionSweepParticle) &&
                 r <= RegionW'(rheo_consts_pkg::RegionSweepMass));
  endfunction
  logic particle_region, slot_region;
  assign particle_region = region_q == RegionW'(rheo_consts_pkg::RegionParticleState) ||
                           region_q == RegionW'(rheo_consts_pkg::RegionSweepParticle);
  assign slot_region = region_q == RegionW'(rheo_consts_pkg::RegionSweepEdge) ||
                       region_q == RegionW'(rheo_consts_pkg::RegionEdgeLength);
  logic entry_done;
  assign entry_done = field_q == last_field_q;

  // The lane and local address of a particle index, in four clocks (a command's start
  // only, so a short path beats a fast lookup): which lanes' slabs start at or below it
  // (empty lanes are skipped), the last of them, the local address, and whether it lies in
  // that slab.
  logic [Lanes-1:0] above_q, above_d;
  logic [IdxCountW-1:0] offset_q, offset_d;  // index - the found lane's first particle
  logic [SAW:0] lane_count_q, lane_count_d;   // the found lane's particles
  logic locate_done;
  logic [LW-1:0] find_lane;
  always_comb begin
    for (int j = 0; j < Lanes; j++) above_d[j] = index_q >= first_q[j] && lcount_q[j] != '0;
    find_lane = '0;
    for (int j = 1; j < Lanes; j++)
      if (above_q[j]) find_lane = LW'(j);
  end
  // The next particle entry: local + 1, or the next lane's first. left_q counts the entries
  // after this one in its slab; per lane, registered from the lane registers: whether the
  // next lane holds particles, and its count less one (no lane multiplexer before a
  // compare on this path).
  logic [Lanes-1:0] next_lane_used_q;
  logic [SAW:0] next_count_m1_q [Lanes];
  logic [SAW:0] left_q, left_d;
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      if (j + 1 < Lanes) begin
        next_lane_used_q[j] <= lcount_q[j+1] != '0;
        next_count_m1_q[j] <= lcount_q[j+1] - 1'b1;
      end else begin
        next_lane_used_q[j] <= 1'b0;
        next_count_m1_q[j] <= '0;
      end
    end
  end
  logic [LW-1:0] next_lane;
  logic [SAW:0] next_local, next_left;
  logic next_in_slab;
  always_comb begin
    next_lane = lane_q;
    next_local = local_q + 1'b1;
    next_left = left_q - 1'b1;
    next_in_slab = in_slab_q;
    if (particle_region && left_q == '0) begin
      next_local = '0;
      next_left = next_count_m1_q[lane_q];
      if (next_lane_used_q[lane_q]) next_lane = lane_q + 1'b1;
      else next_in_slab = 1'b0;
    end
  end
  // The lane above keeps a ghost copy of this slab's last ghost particles: whether the
  // current entry is one of them and its ghost address, registered from local_q (a state
  // entry's write comes with its sixth word, local_q has not changed for five clocks).
  // Per lane, registered from the lane registers (written long before any particle): the
  // local index where the lane above's ghosts begin, and whether it keeps any.
  logic [SAW:0] ghost_from_q [Lanes];
  logic [Lanes-1:0] has_ghost_above_q;
  logic in_ghost_q;
  logic [GAW-1:0] ghost_addr_q;
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < Lanes; j++) begin
      if (j + 1 < Lanes) begin
        ghost_from_q[j] <= lcount_q[j] - (SAW+1)'(lghost_q[j+1]);
        has_ghost_above_q[j] <= lghost_q[j+1] != '0;
      end else begin
        ghost_from_q[j] <= lcount_q[j];
        has_ghost_above_q[j] <= 1'b0;
      end
    end
    in_ghost_q <= has_ghost_above_q[lane_q] && local_q >= ghost_from_q[lane_q];
    ghost_addr_q <= GAW'(local_q - ghost_from_q[lane_q]);
  end

  assign host_we_o = (state_q == StWData) && in_fire && !particle_region && !slot_region &&
                     region_q != RegionW'(rheo_consts_pkg::RegionSweepLane);
  assign region_o = region_q;
  assign field_o = field_q;
  assign index_o = index_q;
  assign wdata_o = s_axis_tdata;
  assign lane_o = lane_q;
  assign local_o = SAW'(local_q);
  logic data_word;
  assign data_word = (state_q == StWData) && in_fire && entry_done;
  assign xp_we_o = data_word && in_slab_q &&
                   region_q == RegionW'(rheo_consts_pkg::RegionParticleState);
  assign xp_wdata_o = {s_axis_tdata, xp_buf_q};
  assign ghost_we_o = xp_we_o && in_ghost_q;
  assign ghost_addr_o = ghost_addr_q;
  assign stat_we_o = data_word && in_slab_q &&
                     region_q == RegionW'(rheo_consts_pkg::RegionSweepParticle);
  // SRAM: a SweepEdge entry {d, tag} is one word; reads of both slot regions.
  assign zbt_valid_o = (data_word && region_q == RegionW'(rheo_consts_pkg::RegionSweepEdge)) ||
                       (state_q == StRFetch && slot_region && wait_q == WaitW'(FetchWait));
  assign zbt_we_o = state_q == StWData;
  assign zbt_addr_o = index_q[NW:0];
  assign zbt_wdata_o = {s_axis_tdata[rheo_consts_pkg::SweepClassBits:0], xp_buf_q[W-1:0]};
  assign go_ahead = (state_q == StRun || state_q == StDrain) && !ahead_q && next_valid_q &&
                    at_period_q;
  assign go_o = (state_q == StRunPlate && (in_fire || next_valid_q)) || go_ahead;
  assign word_taken = in_fire && (state_q == StRunPlate || take_next);
  assign step_end = state_q == StDrain && wait_q == '0;
  assign step_end_o = step_end;
  assign mixed_o = mixed_q || go_ahead;
  assign acc_clear_o = step_end || (state_q == StRunPlate && go_o);
  for (genvar j = 0; j < Lanes; j++) begin : g_lane_regs
    assign count_o[j*(SAW+1) +: SAW+1] = lcount_q[j];
    assign ghost_o[j*(GAW+1) +: GAW+1] = lghost_q[j];
    assign delay_o[j*DelayW +: DelayW] = ldelay_q[j];
  end
  assign gravity_o = gravity_q;
  assign floor_en_o = floor_en_q;
  assign plate_en_o = plate_en_q;
  assign plate_z_o = plate_z_q;
  assign hold_en_o = plate_hold_en_q & plate_prev_valid_q;
  assign prev_valid_o = plate_prev_valid_q;
  assign plate_prev_o = plate_prev_q;

`ifndef SYNTHESIS
  rheo_stream_checker #(
    .W(W), .StateW($bits(state_q)), .NumStates(32'(StForceOut) + 1), .Lanes(Lanes), .BW(LW),
    .DrainW(WaitW), .MaxDrain(FetchWait), .DivStepW(1), .DivSteps(0)
  ) u_checker (
    .clk_i(clk_i), .rst_ni(rst_ni),
    .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
    .s_axis_tlast(s_axis_tlast),
    .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
    .m_axis_tlast(m_axis_tlast),
    // Input while busy: only a run command's next plate word.
    .busy_i(busy_o && !take_next), .state_i(state_q),
    .holds_word_i(state_q == StRSend || state_q == StStatSend || state_q == StForceOut),
    .bank_i(lane_q), .div_rem_i('0), .drain_i(wait_q), .div_step_i(1'b0));
`endif

  logic [W-1:0] status_word;
  always_comb begin
    unique case (field_q)
      FieldW'(0): status_word = status_q;
      FieldW'(1): status_word = step_count_q;
      FieldW'(2): status_word = cycle_count_q;
      default: status_word = 32'(Lanes) | 32'(rheo_consts_pkg::StatusLanesSweep);
    endcase
  end
  // A SweepLane entry's lane (its index; beyond the lanes: a bad command, lane 0 read),
  // registered with the index so that no 24-bit compare sits before the status register.
  logic [LW-1:0] entry_lane;
  logic entry_lane_ok;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      entry_lane <= '0;
      entry_lane_ok <= 1'b1;
    end else begin
      // A clock behind index_q: a lane entry is committed with its fourth word.
      entry_lane_ok <= index_q < IdxCountW'(Lanes);
      entry_lane <= index_q < IdxCountW'(Lanes) ? LW'(index_q) : '0;
    end
  end
  // Words the controller itself holds: the lane registers.
  logic [W-1:0] lane_word;
  always_comb begin
    unique case (field_q)
      FieldW'(rheo_consts_pkg::SweepLaneFirst): lane_word = W'(first_q[entry_lane]);
      FieldW'(rheo_consts_pkg::SweepLaneCount): lane_word = W'(lcount_q[entry_lane]);
      FieldW'(rheo_consts_pkg::SweepLaneGhost): lane_word = W'(lghost_q[entry_lane]);
      default: lane_word = W'(ldelay_q[entry_lane]);
    endcase
  end

  always_comb begin
    state_d = state_q;
    locate_done = 1'b0;
    reading_d = reading_q;
    region_d = region_q;
    last_field_d = last_field_q;
    field_d = field_q;
    count_d = count_q;
    index_d = index_q;
    lane_d = lane_q;
    local_d = local_q;
    in_slab_d = in_slab_q;
    offset_d = offset_q;
    lane_count_d = lane_count_q;
    left_d = left_q;
    wait_d = wait_q;
    clear_d = clear_q;
    out_data_d = out_data_q;
    out_valid_d = out_valid_q;
    out_last_d = out_last_q;
    xp_buf_d = xp_buf_q;
    for (int j = 0; j < Lanes; j++) begin
      first_d[j] = first_q[j];
      lcount_d[j] = lcount_q[j];
      lghost_d[j] = lghost_q[j];
      ldelay_d[j] = ldelay_q[j];
    end
    gravity_d = gravity_q;
    floor_en_d = floor_en_q;
    plate_en_d = plate_en_q;
    plate_z_d = plate_z_q;
    plate_hold_en_d = plate_hold_en_q;
    plate_prev_valid_d = plate_prev_valid_q;
    plate_prev_d = plate_prev_q;
    step_count_d = step_count_q;
    status_d = status_q | lane_flags_i;
    cycle_count_d = (busy_o || go_o) ? cycle_count_q + 32'd1 : cycle_count_q;
    period_m1_d = period_m1_q;
    period_nz_d = period_nz_q;
    since_go_d = go_o ? PeriodW'(1) : since_go_q + PeriodW'(1);
    at_period_d = !go_o && period_nz_q && !passed_q && since_go_q == period_m1_q;
    passed_d = !go_o && (passed_q || at_period_q);
    words_left_d = words_left_q;
    more_d = more_q;
    if (word_taken) begin
      words_left_d = words_left_q - IdxCountW'(1);
      more_d = words_left_q != IdxCountW'(1);
    end
    next_valid_d = next_valid_q;
    next_word_d = next_word_q;
    ahead_d = ahead_q;
    ahead_word_d = ahead_word_q;
    mixed_d = mixed_q;
    if (take_next && s_axis_tvalid) begin
      next_valid_d = 1'b1;
      next_word_d = s_axis_tdata;
    end
    if (go_ahead) begin
      next_valid_d = 1'b0;
      ahead_d = 1'b1;
      ahead_word_d = next_word_q;
      mixed_d = 1'b1;
    end
    if (step_end) mixed_d = 1'b0;

    unique case (state_q)
      StIdle: begin
        if (in_fire) begin
          region_d = hdr_region;
          last_field_d = rheo_consts_pkg::words_per_entry(hdr_region) - FieldW'(1);
          count_d = hdr_count;
          field_d = '0;
          unique case (hdr_opcode)
            OpW'(rheo_consts_pkg::OpWrite), OpW'(rheo_consts_pkg::OpRead): begin
              reading_d = hdr_opcode == OpW'(rheo_consts_pkg::OpRead);
              // A Voigt length is written with its tag (region SweepEdge): EdgeLength is
              // read-only here.
              if (!region_ok(hdr_region) ||
                  (hdr_opcode == OpW'(rheo_consts_pkg::OpWrite) &&
                   hdr_region == RegionW'(rheo_consts_pkg::RegionEdgeLength)))
                status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
              else if (hdr_opcode == OpW'(rheo_consts_pkg::OpRead)) state_d = StRStart;
              else state_d = StWStart;
            end
            OpW'(rheo_consts_pkg::OpRun): begin
              if (hdr_count != 0) state_d = StRunPlate;
              words_left_d = hdr_count;
              more_d = hdr_count != 0;
            end
            OpW'(rheo_consts_pkg::OpStatus): begin
              clear_d = hdr_count[rheo_consts_pkg::StatusClearBit];
              state_d = StStatFetch;
            end
            default: status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
          endcase
        end
      end
      StWStart, StRStart: begin
        if (in_fire) begin
          index_d = word_index;
          wait_d = '0;
          state_d = (count_q == 0) ? StIdle : (reading_q ? StRLocate : StWLocate);
        end
      end
      StWLocate, StRLocate: begin
        // Particle entries: their lane and local address (wait_q counts the four clocks);
        // slot entries: lane and n.
        locate_done = 1'b1;
        if (particle_region) begin
          locate_done = wait_q == WaitW'(3);
          wait_d = wait_q + 1'b1;
          unique case (wait_q)
            WaitW'(0): ;  // above_q is registered from index_q
            WaitW'(1): lane_d = find_lane;
            WaitW'(2): begin
              offset_d = index_q - first_q[lane_q];
              lane_count_d = lcount_q[lane_q];
            end
            default: begin
              local_d = (SAW+1)'(offset_q);
              left_d = lane_count_q - (SAW+1)'(offset_q) - 1'b1;
              in_slab_d = above_q[lane_q] && offset_q < IdxCountW'(lane_count_q);
            end
          endcase
        end else if (slot_region) begin
          in_slab_d = (index_q >> rheo_consts_pkg::SweepSlotLaneShift) < IdxCountW'(Lanes);
          lane_d = in_slab_d ? LW'(index_q >> rheo_consts_pkg::SweepSlotLaneShift) : '0;
        end else begin
          in_slab_d = 1'b1;
        end
        if (locate_done) begin
          wait_d = WaitW'(FetchWait);
          state_d = reading_q ? StRFetch : StWData;
        end
      end
      StWData: begin
        if (in_fire) begin
          if (region_q == RegionW'(rheo_consts_pkg::RegionGlobals)) begin
            unique case (index_q)
              // The particle count and rheo_core's edge rows: the lanes' registers hold
              // what the sweep needs.
              IdxCountW'(rheo_consts_pkg::GlobalNumParticles),
              IdxCountW'(rheo_consts_pkg::GlobalEdgeRows): ;
              IdxCountW'(rheo_consts_pkg::GlobalGravityX): gravity_d[0*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalGravityY): gravity_d[1*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalGravityZ): gravity_d[2*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalSweepPeriod): begin
                period_m1_d = s_axis_tdata[PeriodW-1:0] - PeriodW'(1);
                period_nz_d = s_axis_tdata[PeriodW-1:0] != '0;
              end
              IdxCountW'(rheo_consts_pkg::GlobalControl): begin
                floor_en_d = s_axis_tdata[rheo_consts_pkg::ControlFloorBit];
                plate_en_d = s_axis_tdata[rheo_consts_pkg::ControlPlateBit];
                plate_hold_en_d = s_axis_tdata[rheo_consts_pkg::ControlPlateHoldBit];
                plate_prev_valid_d = 1'b0;
              end
              default: status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
            endcase
          end
          // A lane entry's four words are gathered and committed with the last (the
          // checks then compare registers, not the input word).
          if (region_q == RegionW'(rheo_consts_pkg::RegionSweepLane) && entry_done) begin
            if (!entry_lane_ok || xp_buf_q[1*W +: IdxCountW] > IdxCountW'(SlabDepth) ||
                xp_buf_q[2*W +: IdxCountW] > IdxCountW'(GhostDepth) ||
                (entry_lane == '0 && xp_buf_q[2*W +: IdxCountW] != '0)) begin
              status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
            end else begin
              first_d[entry_lane] = xp_buf_q[0*W +: IdxCountW];
              lcount_d[entry_lane] = (SAW+1)'(xp_buf_q[1*W +: IdxCountW]);
              lghost_d[entry_lane] = (GAW+1)'(xp_buf_q[2*W +: IdxCountW]);
              ldelay_d[entry_lane] = s_axis_tdata[DelayW-1:0];
            end
          end
          if ((particle_region || slot_region) && entry_done && !in_slab_q)
            status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
          // One register per word (a decoder, not a shifter, in front of them).
          for (int f = 0; f < 5; f++)
            if (!entry_done && field_q == FieldW'(f)) xp_buf_d[f*W +: W] = s_axis_tdata;
          if (entry_done) begin
            field_d = '0;
            index_d = index_q + IdxCountW'(1);
            if (particle_region) begin
              lane_d = next_lane;
              local_d = next_local;
              left_d = next_left;
              in_slab_d = next_in_slab;
            end
            count_d = count_q - IdxCountW'(1);
            if (count_q == IdxCountW'(1)) state_d = StIdle;
          end else begin
            field_d = field_q + FieldW'(1);
          end
        end
      end
      StRFetch: begin
        // Memory words arrive the next clock, SRAM words ReadWait clocks after the command
        // (issued in the first fetch clock); the top registers the selected word twice
        // (rheo_sweep_core's read-back), so StRLoad takes it two clocks later.
        if ((!slot_region && wait_q == WaitW'(FetchWait - 2)) || wait_q == '0) state_d = StRLoad;
        else wait_d = wait_q - 1'b1;
      end
      StRLoad: begin
        out_data_d = (region_q == RegionW'(rheo_consts_pkg::RegionSweepLane)) ? lane_word
                                                                               : read_word_i;
        if (((particle_region || slot_region) && !in_slab_q) ||
            (region_q == RegionW'(rheo_consts_pkg::RegionSweepLane) && !entry_lane_ok)) begin
          out_data_d = '0;
          status_d = status_q | lane_flags_i | 32'(rheo_consts_pkg::StatusBadCommand);
        end
        out_valid_d = 1'b1;
        out_last_d = (count_q == IdxCountW'(1)) && entry_done;
        state_d = StRSend;
      end
      StRSend: begin
        if (out_fire) begin
          out_valid_d = 1'b0;
          out_last_d = 1'b0;
          wait_d = WaitW'(FetchWait);
          if (entry_done) begin
            field_d = '0;
            index_d = index_q + IdxCountW'(1);
            if (particle_region) begin
              lane_d = next_lane;
              local_d = next_local;
              left_d = next_left;
              in_slab_d = next_in_slab;
            end
            count_d = count_q - IdxCountW'(1);
            state_d = (count_q == IdxCountW'(1)) ? StIdle : StRFetch;
          end else begin
            field_d = field_q + FieldW'(1);
            state_d = StRFetch;
          end
        end
      end
      StStatFetch: begin
        out_data_d = status_word;
        out_valid_d = 1'b1;
        out_last_d = (field_q == FieldW'(rheo_consts_pkg::StatusWords - 1));
        state_d = StStatSend;
      end
      StStatSend: begin
        if (out_fire) begin
          out_valid_d = 1'b0;
          out_last_d = 1'b0;
          if (field_q == FieldW'(rheo_consts_pkg::StatusWords - 1)) begin
            field_d = '0;
            if (clear_q) status_d = lane_flags_i;
            state_d = StIdle;
          end else begin
            field_d = field_q + FieldW'(1);
            state_d = StStatFetch;
          end
        end
      end
      StRunPlate: begin
        if (go_o) begin
          plate_z_d = next_valid_q ? next_word_q : s_axis_tdata;
          next_valid_d = 1'b0;
          plate_prev_d = plate_z_q;
          plate_prev_valid_d = 1'b1;
          state_d = StRun;
        end
      end
      StRun: begin
        if (&done_i) begin
          // The last plate forces still climb the lanes' sum tree (rheo_sweep_plate_acc).
          wait_d = WaitW'(rheo_consts_pkg::SweepPlateTreeLevels - 1);
          state_d = StDrain;
        end
      end
      StDrain: begin
        if (wait_q != '0) begin
          wait_d = wait_q - 1'b1;
        end else begin
          // The last plate force was added to the accumulator in this clock's edge.
          out_data_d = rheo_consts_pkg::sat_word(WideW'(signed'(plate_acc_i)));
          if (rheo_consts_pkg::clips(WideW'(signed'(plate_acc_i)), W))
            status_d = status_q | lane_flags_i | 32'(rheo_consts_pkg::StatusPlateSat);
          out_valid_d = 1'b1;
          out_last_d = (count_q == IdxCountW'(1));
          step_count_d = step_count_q + 32'd1;
          state_d = StForceOut;
          // The step gone ahead: its plate word for the MPMs from now on.
          if (ahead_q) begin
            plate_z_d = ahead_word_q;
            plate_prev_d = plate_z_q;
            plate_prev_valid_d = 1'b1;
          end
        end
      end
      StForceOut: begin
        if (out_fire) begin
          out_valid_d = 1'b0;
          out_last_d = 1'b0;
          count_d = count_q - IdxCountW'(1);
          ahead_d = 1'b0;
          state_d = ahead_q ? StRun : (count_q == IdxCountW'(1)) ? StIdle : StRunPlate;
        end
      end
      default: state_d = StIdle;
    endcase
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= StIdle;
      reading_q <= 1'b0;
      region_q <= '0;
      last_field_q <= '0;
      field_q <= '0;
      count_q <= '0;
      index_q <= '0;
      lane_q <= '0;
      local_q <= '0;
      in_slab_q <= 1'b0;
      above_q <= '0;
      offset_q <= '0;
      lane_count_q <= '0;
      left_q <= '0;
      wait_q <= '0;
      clear_q <= 1'b0;
      out_data_q <= '0;
      out_valid_q <= 1'b0;
      out_last_q <= 1'b0;
      xp_buf_q <= '0;
      for (int j = 0; j < Lanes; j++) begin
        first_q[j] <= '0;
        lcount_q[j] <= '0;
        lghost_q[j] <= '0;
        ldelay_q[j] <= '0;
      end
      gravity_q <= '0;
      floor_en_q <= 1'b0;
      plate_en_q <= 1'b0;
      plate_z_q <= '0;
      plate_hold_en_q <= 1'b0;
      plate_prev_valid_q <= 1'b0;
      plate_prev_q <= '0;
      status_q <= '0;
      step_count_q <= '0;
      cycle_count_q <= '0;
      since_go_q <= '0;
      next_valid_q <= 1'b0;
      next_word_q <= '0;
      ahead_q <= 1'b0;
      ahead_word_q <= '0;
      mixed_q <= 1'b0;
      period_m1_q <= '0;
      period_nz_q <= 1'b0;
      words_left_q <= '0;
      more_q <= 1'b0;
      at_period_q <= 1'b0;
      passed_q <= 1'b0;
    end else begin
      state_q <= state_d;
      reading_q <= reading_d;
      region_q <= region_d;
      last_field_q <= last_field_d;
      field_q <= field_d;
      count_q <= count_d;
      index_q <= index_d;
      lane_q <= lane_d;
      local_q <= local_d;
      in_slab_q <= in_slab_d;
      above_q <= above_d;
      offset_q <= offset_d;
      lane_count_q <= lane_count_d;
      left_q <= left_d;
      wait_q <= wait_d;
      clear_q <= clear_d;
      out_data_q <= out_data_d;
      out_valid_q <= out_valid_d;
      out_last_q <= out_last_d;
      xp_buf_q <= xp_buf_d;
      for (int j = 0; j < Lanes; j++) begin
        first_q[j] <= first_d[j];
        lcount_q[j] <= lcount_d[j];
        lghost_q[j] <= lghost_d[j];
        ldelay_q[j] <= ldelay_d[j];
      end
      gravity_q <= gravity_d;
      floor_en_q <= floor_en_d;
      plate_en_q <= plate_en_d;
      plate_z_q <= plate_z_d;
      plate_hold_en_q <= plate_hold_en_d;
      plate_prev_valid_q <= plate_prev_valid_d;
      plate_prev_q <= plate_prev_d;
      status_q <= status_d;
      step_count_q <= step_count_d;
      cycle_count_q <= cycle_count_d;
      since_go_q <= since_go_d;
      next_valid_q <= next_valid_d;
      next_word_q <= next_word_d;
      ahead_q <= ahead_d;
      ahead_word_q <= ahead_word_d;
      mixed_q <= mixed_d;
      period_m1_q <= period_m1_d;
      period_nz_q <= period_nz_d;
      words_left_q <= words_left_d;
      more_q <= more_d;
      at_period_q <= at_period_d;
      passed_q <= passed_d;
    end
  end
endmodule
