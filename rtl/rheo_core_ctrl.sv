// Command controller of rheo_core: decodes the command stream (hls/frame_format.hpp), owns
// every control register (entry counters, global registers, status, output word) and
// sequences a step's passes. The datapath (memories, lanes, crossbar, read-back) only sees
// its decoded strobes and counters, so the protocol lives in one place and the formal flow
// can prove it with the datapath cut away.
//
// Two processes: the always_comb block computes every register's next value (*_d) from
// the current state, and one always_ff registers them (*_q), so each state's whole effect
// is visible in one case item and no register is assigned from two processes.
//
// The command's start index is turned into (bank, local) = (index % Lanes, index / Lanes)
// by a shift-subtract division, one quotient bit per clock (IdxCountW clocks): a divider
// by a non-power-of-two lane count would otherwise sit on the index path.
module rheo_core_ctrl #(
  parameter int Lanes = 1,
  parameter int MaxParticles = 4096,
  parameter int PDepth = 4096,          // particles per bank
  parameter int EDepth = 65536,         // edge slots per lane
  parameter int W = 32,
  parameter int MaxwellArms = 0,        // parallel Maxwell arms: a region pair each
  parameter int SeriesDamper = 0,       // force-dependent series damper: its material region
  parameter int StrainHardening = 0,    // strain hardening: its material region, a longer drain
  parameter int ToolContact = 0,        // the tool unit: its registers and reaction, a longer drain
  localparam int BW = (Lanes > 1) ? $clog2(Lanes) : 1,
  localparam int IdxCountW = rheo_consts_pkg::IdxCountW,
  localparam int RegionW = rheo_consts_pkg::HeaderRegionBits,
  localparam int FieldW = rheo_consts_pkg::EntryFieldW,
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW,
  localparam int B = rheo_consts_pkg::OperandBits,
  localparam int CoefW = rheo_consts_pkg::CoefW
) (
  input  logic         clk_i,
  input  logic         rst_ni,
  // Command and response streams (the core's ports).
  input  logic [W-1:0] s_axis_tdata,
  input  logic         s_axis_tvalid,
  output logic         s_axis_tready,
  input  logic         s_axis_tlast,     // only the stream checker looks at it
  output logic [W-1:0] m_axis_tdata,
  output logic         m_axis_tvalid,
  input  logic         m_axis_tready,
  output logic         m_axis_tlast,
  output logic         busy_o,
  // Host access to the memories: the entry being written or read.
  output logic                 host_we_o,        // s_axis_tdata is a word of an entry
  output logic                 host_wdata_o,     // WRITE data phase: bank port B is the host's
  output logic [RegionW-1:0]   region_o,
  output logic [FieldW-1:0]    field_o,          // word within the entry
  output logic [IdxCountW-1:0] index_o,
  output logic [IdxCountW-1:0] local_o,          // index / Lanes
  output logic [BW-1:0]        bank_o,           // index % Lanes
  output logic                 particle_ok_o,    // local_o addresses a particle bank word
  output logic                 edge_ok_o,        // local_o addresses an edge slot
  // Passes of a step.
  output logic [IdxCountW-1:0] row_o,            // edge row, particle row, or clear address
  output logic                 clearing_sums_o,  // after reset: force sums being cleared
  output logic                 tem_pass_o,       // edge rows are being issued
  output logic                 edge_phase_o,     // edge pass or its drain
  output logic                 mpm_phase_o,      // particle rows are being issued
  output logic                 edge_issue_o,     // row_o is an edge row of the schedule
  output logic [Lanes-1:0]     mpm_issue_o,      // lane j's particle of row_o exists
  output logic                 plate_start_o,    // a step's plate word is taken
  // Global registers the lanes' MPMs use.
  output logic [3*W-1:0]       gravity_o,
  output logic                 floor_en_o,
  output logic                 plate_en_o,
  output logic [W-1:0]         plate_z_o,
  output logic                 hold_en_o,
  output logic                 prev_valid_o,
  output logic [W-1:0]         plate_prev_o,
  // From the datapath.
  input  logic [W-1:0]         read_word_i,      // memory word of the entry (read-back mux)
  input  logic [31:0]          lane_flags_i,     // status flags raised this clock
  input  logic [PlateAccW-1:0] plate_acc_i,      // plate force of the step, complete in drain
  // The tool unit's registers (region RegionTool; ToolContact = 1) and the sums of the
  // tool's forces on the particles of the step, complete in the drain.
  output logic [1:0]           tool_kind_o,
  output logic [3*W-1:0]       tool_c_o,
  output logic [3*W-1:0]       tool_dc_o,
  output logic [3*B-1:0]       tool_a_o,
  output logic [W-1:0]         tool_reach_o,
  output logic [W-1:0]         tool_half_len_o,
  output logic [CoefW-1:0]     tool_kt_o,
  output logic [CoefW-1:0]     tool_ct_o,
  output logic [CoefW-1:0]     tool_mu_o,
  output logic [CoefW-1:0]     tool_spin_o,
  input  logic [3*PlateAccW-1:0] tool_acc_i
);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int TemDrain = rheo_consts_pkg::TemDrain +
                            ((StrainHardening == 0) ? 0 :
                             ((SeriesDamper != 0) ? rheo_consts_pkg::HardDamperTemExtra
                                                  : rheo_consts_pkg::HardTemExtra));
  // The tool unit and its sum stage sit in front of the MPM (hls::EdgeElement::mpm_drain_cycles).
  localparam int MpmDrain = rheo_consts_pkg::MpmDrain +
                            ((ToolContact != 0) ? rheo_consts_pkg::ToolLatency + 1 : 0);
  localparam int OpW = rheo_consts_pkg::HeaderOpcodeBits;
  localparam int CoreRegions = rheo_consts_pkg::NumBaseRegions + 2 * MaxwellArms;
  localparam int MaxDrain = TemDrain > MpmDrain ? TemDrain : MpmDrain;
  // Wide enough for the longer of the two drains (they follow the module latencies).
  localparam int DrainW = $clog2(MaxDrain + 1);
  // The division counter ends one past its last step.
  localparam int DivStepW = $clog2(IdxCountW + 1);
  localparam int TrialW = BW + 1;

  typedef enum logic [4:0] {
    StClearSums, StIdle, StWStart, StWData, StRStart, StDivide, StRFetch, StRLoad, StRSend,
    StStatFetch, StStatSend, StRunPlate, StTem, StTemDrain, StMpm, StMpmDrain, StForceOut
  } state_e;

  // ---------------------------------------------------------------- registers
  state_e state_q, state_d;
  logic reading_q, reading_d;                      // the command being decoded is a READ
  logic [RegionW-1:0] region_q, region_d;
  // Index of an entry's last word, registered with the command's region so that the
  // word-count lookup and its subtraction stay off the next-state path.
  logic [FieldW-1:0] last_field_q, last_field_d;
  logic [IdxCountW-1:0] count_q, count_d;          // entries (or steps) remaining
  logic [IdxCountW-1:0] index_q, index_d;          // current entry
  logic [IdxCountW-1:0] local_q, local_d;          // current entry's local address
  logic [BW-1:0] bank_q, bank_d;                   // current entry's bank or lane
  logic [IdxCountW-1:0] div_num_q, div_num_d;
  logic [BW-1:0] div_rem_q, div_rem_d;             // remainder so far (< Lanes)
  logic [DivStepW-1:0] div_step_q, div_step_d;
  logic [FieldW-1:0] field_q, field_d;             // word within the entry
  logic clear_q, clear_d;                          // status: clear after reading
  logic [IdxCountW-1:0] row_q, row_d;              // edge row / particle row of the passes
  logic [IdxCountW-1:0] base_q, base_d;            // first particle index of the row
  logic [DrainW-1:0] drain_q, drain_d;
  logic [W-1:0] out_data_q, out_data_d;
  logic out_valid_q, out_valid_d, out_last_q, out_last_d;
  logic [IdxCountW-1:0] num_particles_q, num_particles_d, edge_rows_q, edge_rows_d;
  logic [3*W-1:0] gravity_q, gravity_d;     // {z, y, x}
  logic floor_en_q, floor_en_d, plate_en_q, plate_en_d;
  logic [W-1:0] plate_z_q, plate_z_d;
  // Hold while pushing: a particle the plate held in the previous step sits exactly at
  // that step's plate height, so the previous height (valid from the second step after a
  // control write) stands in for a held bit per particle.
  logic plate_hold_en_q, plate_hold_en_d, plate_prev_valid_q, plate_prev_valid_d;
  logic [W-1:0] plate_prev_q, plate_prev_d;
  logic [31:0] status_q, status_d, step_count_q, step_count_d, cycle_count_q, cycle_count_d;
  // The tool unit's registers, and the reaction words of the last step.
  // Flat vectors (register r at [r*W +: W]): Yosys 0.23 copies unpacked arrays poorly.
  localparam int ToolRegs = rheo_consts_pkg::ToolRegisters;
  logic [ToolRegs*W-1:0] tool_word_q, tool_word_d;
  logic [3*W-1:0] reaction_q, reaction_d;

  // A tool register as it reads back.
  function automatic logic [W-1:0] tool_reg_word(input int r);
    if (r == rheo_consts_pkg::ToolKind) tool_reg_word = W'(tool_word_q[r*W +: 2]);
    else if (r >= rheo_consts_pkg::ToolAx && r <= rheo_consts_pkg::ToolAz)
      tool_reg_word = W'($signed(tool_word_q[r*W +: B]));
    else if (r == rheo_consts_pkg::ToolKt || r == rheo_consts_pkg::ToolCt ||
             r == rheo_consts_pkg::ToolMu || r == rheo_consts_pkg::ToolSpin)
      tool_reg_word = W'(tool_word_q[r*W +: CoefW]);
    else tool_reg_word = tool_word_q[r*W +: W];
  endfunction

  // ---------------------------------------------------------------- command fields
  logic [OpW-1:0] hdr_opcode;
  logic [RegionW-1:0] hdr_region;
  logic [IdxCountW-1:0] hdr_count, word_index;
  assign hdr_opcode = s_axis_tdata[rheo_consts_pkg::HeaderOpcodeShift +: OpW];
  assign hdr_region = s_axis_tdata[rheo_consts_pkg::HeaderRegionShift +: RegionW];
  assign hdr_count = s_axis_tdata[rheo_consts_pkg::HeaderCountShift +: IdxCountW];
  // Index words and the count-like global registers use the same low bits.
  assign word_index = s_axis_tdata[IdxCountW-1:0];

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

  logic entry_done;
  assign entry_done = (field_q == last_field_q);

  // ---------------------------------------------------------------- datapath controls
  assign host_we_o = (state_q == StWData) && in_fire;
  assign host_wdata_o = (state_q == StWData);
  assign region_o = region_q;
  assign field_o = field_q;
  assign index_o = index_q;
  assign local_o = local_q;
  assign bank_o = bank_q;
  assign particle_ok_o = local_q < IdxCountW'(PDepth);
  assign edge_ok_o = local_q < IdxCountW'(EDepth);
  assign row_o = row_q;
  // After reset the force sums are cleared once (a reset in the middle of a step would
  // otherwise leave partial sums behind); from then on every MPM pass clears what it read.
  assign clearing_sums_o = (state_q == StClearSums);
  assign tem_pass_o = (state_q == StTem);
  assign edge_phase_o = (state_q == StTem) || (state_q == StTemDrain);
  assign mpm_phase_o = (state_q == StMpm);
  assign edge_issue_o = (state_q == StTem) && (row_q < edge_rows_q);
  for (genvar j = 0; j < Lanes; j++) begin : g_issue
    assign mpm_issue_o[j] = (state_q == StMpm) && (base_q + IdxCountW'(j) < num_particles_q);
  end
  assign plate_start_o = (state_q == StRunPlate) && in_fire;
  assign gravity_o = gravity_q;
  assign floor_en_o = floor_en_q;
  assign plate_en_o = plate_en_q;
  assign plate_z_o = plate_z_q;
  assign hold_en_o = plate_hold_en_q & plate_prev_valid_q;
  assign prev_valid_o = plate_prev_valid_q;
  assign plate_prev_o = plate_prev_q;
  assign tool_kind_o = tool_word_q[rheo_consts_pkg::ToolKind*W +: 2];
  for (genvar i = 0; i < 3; i++) begin : g_tool_vec
    assign tool_c_o[i*W +: W] = tool_word_q[(rheo_consts_pkg::ToolCx + i)*W +: W];
    assign tool_dc_o[i*W +: W] = tool_word_q[(rheo_consts_pkg::ToolDcx + i)*W +: W];
    assign tool_a_o[i*B +: B] = tool_word_q[(rheo_consts_pkg::ToolAx + i)*W +: B];
  end
  assign tool_reach_o = tool_word_q[rheo_consts_pkg::ToolReach*W +: W];
  assign tool_half_len_o = tool_word_q[rheo_consts_pkg::ToolHalfLength*W +: W];
  assign tool_kt_o = tool_word_q[rheo_consts_pkg::ToolKt*W +: CoefW];
  assign tool_ct_o = tool_word_q[rheo_consts_pkg::ToolCt*W +: CoefW];
  assign tool_mu_o = tool_word_q[rheo_consts_pkg::ToolMu*W +: CoefW];
  assign tool_spin_o = tool_word_q[rheo_consts_pkg::ToolSpin*W +: CoefW];
  // The word a READ of the tool's regions returns (as the core holds the registers: the
  // kind's two bits, the operands sign-extended, the coefficients' packed bits).
  logic [W-1:0] tool_read_word;
  always_comb begin
    tool_read_word = '0;
    if (region_q == RegionW'(rheo_consts_pkg::RegionToolReaction)) begin
      for (int i = 0; i < 3; i++)
        if (index_q == IdxCountW'(i)) tool_read_word = reaction_q[i*W +: W];
    end else begin
      for (int r = 0; r < ToolRegs; r++)
        if (index_q == IdxCountW'(r)) tool_read_word = tool_reg_word(r);
    end
  end

`ifndef SYNTHESIS
  // Stream protocol and FSM invariants (rtl/rheo_stream_checker.sv): asserted in every
  // verilated core (--assert) and proved by the formal flow; synthesis leaves them out.
  // Instantiated here because the state and the counters it checks are this module's.
  rheo_stream_checker #(
    .W(W), .StateW($bits(state_q)), .NumStates(32'(StForceOut) + 1), .Lanes(Lanes), .BW(BW),
    .DrainW(DrainW), .MaxDrain(MaxDrain - 1), .DivStepW(DivStepW), .DivSteps(IdxCountW)
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

  // ---------------------------------------------------------------- status response
  logic [W-1:0] status_word;
  always_comb begin
    unique case (field_q)
      FieldW'(0): status_word = status_q;
      FieldW'(1): status_word = step_count_q;
      FieldW'(2): status_word = cycle_count_q;
      default: status_word = 32'(Lanes);
    endcase
  end

  // Bank and local address of entry index_q + 1, taken by WRITE and READ commands when an
  // entry is done.
  logic [BW-1:0] next_bank;
  logic [IdxCountW-1:0] next_local;
  always_comb begin
    if (bank_q == BW'(Lanes - 1)) begin
      next_bank = '0;
      next_local = local_q + IdxCountW'(1);
    end else begin
      next_bank = bank_q + BW'(1);
      next_local = local_q;
    end
  end

  // One step of the division of the start index by Lanes.
  logic [TrialW-1:0] div_trial;
  logic [BW-1:0] div_rem_next;
  logic div_take;
  assign div_trial = {div_rem_q, div_num_q[IdxCountW-1]};
  assign div_take = div_trial >= TrialW'(Lanes);
  assign div_rem_next = BW'(div_take ? div_trial - TrialW'(Lanes) : div_trial);

  // Minus the sums of the tool's forces (the reaction), one wide word per axis, registered:
  // the sums are complete about eight clocks before the MPM drain ends (the tool unit's last
  // force precedes the MPM's last particle by the MPM's latency), so the negation's carry
  // chain and the narrowing's compare sit in different clocks.
  logic [3*WideW-1:0] tool_neg;
  always_ff @(posedge clk_i) begin
    for (int i = 0; i < 3; i++)
      tool_neg[i*WideW +: WideW] <= WideW'(0) - WideW'(signed'(tool_acc_i[i*PlateAccW +: PlateAccW]));
  end

  // ---------------------------------------------------------------- next state
  always_comb begin
    state_d = state_q;
    reading_d = reading_q;
    region_d = region_q;
    last_field_d = last_field_q;
    count_d = count_q;
    index_d = index_q;
    local_d = local_q;
    bank_d = bank_q;
    div_num_d = div_num_q;
    div_rem_d = div_rem_q;
    div_step_d = div_step_q;
    field_d = field_q;
    clear_d = clear_q;
    row_d = row_q;
    base_d = base_q;
    drain_d = drain_q;
    out_data_d = out_data_q;
    out_valid_d = out_valid_q;
    out_last_d = out_last_q;
    num_particles_d = num_particles_q;
    edge_rows_d = edge_rows_q;
    gravity_d = gravity_q;
    floor_en_d = floor_en_q;
    plate_en_d = plate_en_q;
    plate_z_d = plate_z_q;
    plate_hold_en_d = plate_hold_en_q;
    plate_prev_valid_d = plate_prev_valid_q;
    plate_prev_d = plate_prev_q;
    step_count_d = step_count_q;
    tool_word_d = tool_word_q;
    reaction_d = reaction_q;
    // Flags are sticky; a later assignment in a state replaces this one (a bad command's
    // flag is set from status_q alone, as before the split).
    status_d = status_q | lane_flags_i;
    cycle_count_d = busy_o ? cycle_count_q + 32'd1 : cycle_count_q;

    unique case (state_q)
      StClearSums: begin
        if (row_q == IdxCountW'(PDepth - 1)) begin
          row_d = '0;
          state_d = StIdle;
        end else begin
          row_d = row_q + IdxCountW'(1);
        end
      end
      StIdle: begin
        if (in_fire) begin
          region_d = hdr_region;
          last_field_d = rheo_consts_pkg::words_per_entry(hdr_region) - FieldW'(1);
          count_d = hdr_count;
          field_d = '0;
          unique case (hdr_opcode)
            OpW'(rheo_consts_pkg::OpWrite), OpW'(rheo_consts_pkg::OpRead): begin
              reading_d = hdr_opcode == OpW'(rheo_consts_pkg::OpRead);
              if (hdr_region >= RegionW'(CoreRegions) &&
                  !(SeriesDamper != 0 &&
                    hdr_region == RegionW'(rheo_consts_pkg::RegionMaterialDamper)) &&
                  !(StrainHardening != 0 &&
                    hdr_region == RegionW'(rheo_consts_pkg::RegionMaterialHardening)) &&
                  !(ToolContact != 0 &&
                    (hdr_region == RegionW'(rheo_consts_pkg::RegionTool) ||
                     hdr_region == RegionW'(rheo_consts_pkg::RegionToolReaction))))
                status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
              else if (hdr_opcode == OpW'(rheo_consts_pkg::OpRead))
                state_d = StRStart;
              else state_d = StWStart;
            end
            OpW'(rheo_consts_pkg::OpRun): begin
              if (hdr_count != 0) state_d = StRunPlate;
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
          div_num_d = word_index;
          div_rem_d = '0;
          div_step_d = '0;
          local_d = '0;
          state_d = (count_q == 0) ? StIdle : StDivide;
        end
      end
      StDivide: begin
        div_num_d = div_num_q << 1;
        div_rem_d = div_rem_next;
        local_d = {local_q[IdxCountW-2:0], div_take};
        div_step_d = div_step_q + DivStepW'(1);
        if (div_step_q == DivStepW'(IdxCountW - 1)) begin
          bank_d = div_rem_next;
          state_d = reading_q ? StRFetch : StWData;
        end
      end
      StWData: begin
        if (in_fire) begin
          if (region_q == RegionW'(rheo_consts_pkg::RegionGlobals)) begin
            unique case (index_q)
              // Counts beyond the memories would wrap the addresses: refused.
              IdxCountW'(rheo_consts_pkg::GlobalNumParticles): begin
                if (word_index > IdxCountW'(MaxParticles))
                  status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                else num_particles_d = word_index;
              end
              IdxCountW'(rheo_consts_pkg::GlobalEdgeRows): begin
                if (word_index > IdxCountW'(EDepth))
                  status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
                else edge_rows_d = word_index;
              end
              IdxCountW'(rheo_consts_pkg::GlobalGravityX): gravity_d[0*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalGravityY): gravity_d[1*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalGravityZ): gravity_d[2*W +: W] = s_axis_tdata;
              IdxCountW'(rheo_consts_pkg::GlobalControl): begin
                floor_en_d = s_axis_tdata[rheo_consts_pkg::ControlFloorBit];
                plate_en_d = s_axis_tdata[rheo_consts_pkg::ControlPlateBit];
                plate_hold_en_d = s_axis_tdata[rheo_consts_pkg::ControlPlateHoldBit];
                plate_prev_valid_d = 1'b0;
              end
              default: status_d = status_q | 32'(rheo_consts_pkg::StatusBadCommand);
            endcase
          end
          if (ToolContact != 0 && region_q == RegionW'(rheo_consts_pkg::RegionTool)) begin
            for (int r = 0; r < ToolRegs; r++)
              if (index_q == IdxCountW'(r)) tool_word_d[r*W +: W] = s_axis_tdata;
          end
          if (entry_done) begin
            field_d = '0;
            index_d = index_q + IdxCountW'(1);
            bank_d = next_bank;
            local_d = next_local;
            count_d = count_q - IdxCountW'(1);
            if (count_q == IdxCountW'(1)) state_d = StIdle;
          end else begin
            field_d = field_q + FieldW'(1);
          end
        end
      end
      StRFetch: state_d = StRLoad;
      StRLoad: begin
        out_data_d = (ToolContact != 0 &&
                      (region_q == RegionW'(rheo_consts_pkg::RegionTool) ||
                       region_q == RegionW'(rheo_consts_pkg::RegionToolReaction)))
                         ? tool_read_word : read_word_i;
        out_valid_d = 1'b1;
        out_last_d = (count_q == IdxCountW'(1)) && entry_done;
        state_d = StRSend;
      end
      StRSend: begin
        if (out_fire) begin
          out_valid_d = 1'b0;
          out_last_d = 1'b0;
          if (entry_done) begin
            field_d = '0;
            index_d = index_q + IdxCountW'(1);
            bank_d = next_bank;
            local_d = next_local;
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
        if (in_fire) begin
          plate_z_d = s_axis_tdata;
          plate_prev_d = plate_z_q;
          plate_prev_valid_d = 1'b1;
          row_d = '0;
          state_d = StTem;
        end
      end
      StTem: begin
        if (row_q + IdxCountW'(1) >= edge_rows_q) begin
          row_d = '0;
          drain_d = DrainW'(TemDrain - 1);
          state_d = StTemDrain;
        end else begin
          row_d = row_q + IdxCountW'(1);
        end
      end
      StTemDrain: begin
        base_d = '0;
        if (drain_q == 0) state_d = StMpm;
        else drain_d = drain_q - 1'b1;
      end
      StMpm: begin
        if (base_q + IdxCountW'(Lanes) >= num_particles_q) begin
          row_d = '0;
          drain_d = DrainW'(MpmDrain - 1);
          state_d = StMpmDrain;
        end else begin
          row_d = row_q + IdxCountW'(1);
          base_d = base_q + IdxCountW'(Lanes);
        end
      end
      StMpmDrain: begin
        if (drain_q == 0) begin
          out_data_d = rheo_consts_pkg::sat_word(WideW'(signed'(plate_acc_i)));
          if (rheo_consts_pkg::clips(WideW'(signed'(plate_acc_i)), W))
            status_d = status_q | lane_flags_i | 32'(rheo_consts_pkg::StatusPlateSat);
          if (ToolContact != 0) begin
            // the reaction: minus the sum of the tool's forces on the particles
            for (int i = 0; i < 3; i++) begin
              reaction_d[i*W +: W] = rheo_consts_pkg::sat_word(tool_neg[i*WideW +: WideW]);
              if (rheo_consts_pkg::clips(tool_neg[i*WideW +: WideW], W))
                status_d = status_d | lane_flags_i | 32'(rheo_consts_pkg::StatusToolSat);
            end
          end
          out_valid_d = 1'b1;
          out_last_d = (count_q == IdxCountW'(1));
          step_count_d = step_count_q + 32'd1;
          state_d = StForceOut;
        end else begin
          drain_d = drain_q - 1'b1;
        end
      end
      StForceOut: begin
        if (out_fire) begin
          out_valid_d = 1'b0;
          out_last_d = 1'b0;
          count_d = count_q - IdxCountW'(1);
          state_d = (count_q == IdxCountW'(1)) ? StIdle : StRunPlate;
        end
      end
      default: state_d = StIdle;
    endcase
  end

  // ---------------------------------------------------------------- registers
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= StClearSums;
      reading_q <= 1'b0;
      region_q <= '0;
      last_field_q <= rheo_consts_pkg::words_per_entry(RegionW'(0)) - FieldW'(1);
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
      tool_word_q <= '0;
      reaction_q <= '0;
    end else begin
      state_q <= state_d;
      reading_q <= reading_d;
      region_q <= region_d;
      last_field_q <= last_field_d;
      count_q <= count_d;
      index_q <= index_d;
      local_q <= local_d;
      bank_q <= bank_d;
      div_num_q <= div_num_d;
      div_rem_q <= div_rem_d;
      div_step_q <= div_step_d;
      field_q <= field_d;
      clear_q <= clear_d;
      row_q <= row_d;
      base_q <= base_d;
      drain_q <= drain_d;
      out_data_q <= out_data_d;
      out_valid_q <= out_valid_d;
      out_last_q <= out_last_d;
      num_particles_q <= num_particles_d;
      edge_rows_q <= edge_rows_d;
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
      tool_word_q <= tool_word_d;
      reaction_q <= reaction_d;
    end
  end
endmodule
