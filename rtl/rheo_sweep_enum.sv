// The edge stream of one sweep lane: from the particles' static words it produces one slot
// per clock, the order every step follows (docs/sweep_core.md, "A lane's stream"):
//   - the cross sweep: ghost particle a = 0 .. ghost-1 (the lane below's particle
//     prev_count - ghost + a), its edges into this slab: offsets k with o_k >= ghost - a
//     (the end, local index o_k - (ghost - a), lies in this slab), at least
//     SweepCrossMinSlots slots;
//   - the own sweep: particle s = 0 .. count-1, its edges inside the slab: offsets k with
//     s + o_k < count, at least SweepOwnMinSlots slots (the slot that reads the particle
//     and the one that writes its MPM result share a memory port);
//   - within a particle, its offsets in increasing k; a slot without an edge is padding.
// A slot carries the particle, the offset, its number n in the stream (its SRAM word:
// device n % 2, address n / 2; hls/sweep_format.hpp) and whether it is the particle's first
// and last slot. Nothing depends on the data, so a lane
// takes max(1, cross edges) per ghost particle and max(2, own edges) per own particle.
//
// Timing: go_i in clock 0 (the plate word is taken); the static words are read from
// clock 1 (three clocks to a prefetch queue entry: read, mask, count its edges); the lane
// waits delay_i clocks more and
// the first slot is in the slot registers in clock SweepLeadClocks + delay_i; then one slot
// per clock, with no gap (the queue keeps ahead: an assertion checks it).
// own_mask_o of a particle: has_cross_o says whether some of its edges leave the slab (they
// are the lane above's cross edges, whose start sums wait in that lane's ghost sums).
module rheo_sweep_enum #(
  parameter int SlabDepth = 1024,
  parameter int GhostDepth = 256,
  parameter int DelayW = 24,
  localparam int SAW = $clog2(SlabDepth),
  localparam int GAW = $clog2(GhostDepth),
  localparam int Offsets = rheo_consts_pkg::SweepOffsets,
  localparam int OffW = rheo_consts_pkg::SweepOffsetBits,
  localparam int KW = $clog2(Offsets),
  localparam int StatW = rheo_consts_pkg::SweepStaticBits,
  localparam int MassW = rheo_consts_pkg::SweepMassBits,
  localparam int NW = rheo_consts_pkg::ZbtAddrBits
) (
  input  logic                    clk_i,
  input  logic                    rst_ni,
  input  logic                    go_i,
  input  logic [SAW:0]            count_i,
  input  logic [GAW:0]            ghost_i,
  input  logic [SAW:0]            prev_count_i,
  input  logic [DelayW-1:0]       delay_i,
  input  logic [Offsets*OffW-1:0] offsets_i,
  // Static words: this lane's (port A, registered) and the lane below's (its port B).
  output logic [SAW-1:0]          own_stat_addr_o,
  input  logic [StatW-1:0]        own_stat_i,
  output logic [SAW-1:0]          prev_stat_addr_o,
  input  logic [StatW-1:0]        prev_stat_i,
  // The slot of this clock.
  output logic                    slot_o,       // a slot (edge or padding)
  output logic                    edge_o,       // the slot holds an edge
  output logic                    first_o,      // the particle's first slot
  output logic                    last_o,       // the particle's last slot
  output logic                    cross_o,      // a ghost particle's slot
  output logic [SAW-1:0]          idx_o,        // ghost address or own local index
  output logic [KW-1:0]           k_o,          // the edge's offset
  output logic [NW:0]             n_o,          // the slot's number: its SRAM word
  output logic [MassW-1:0]        mass_o,       // own particle: mass class
  output logic                    fixed_o,
  output logic                    plate_o,
  output logic                    has_in_o,     // some edge ends at it
  output logic                    has_cross_o,  // some edge leaves the slab from it
  output logic                    step_first_o, // the step's first slot
  output logic                    busy_o,       // a step's stream not yet ended
  output logic                    starved_o     // the queue was empty with slots to come
);
  localparam int QDepth = 8;
  localparam int QAW = $clog2(QDepth);
  localparam int CntW = KW + 2;  // slots of one particle (at most Offsets)
  localparam int OwnMin = rheo_consts_pkg::SweepOwnMinSlots;
  localparam int CrossMin = rheo_consts_pkg::SweepCrossMinSlots;

  logic [OffW-1:0] off [Offsets];
  for (genvar k = 0; k < Offsets; k++) begin : g_off
    assign off[k] = offsets_i[k*OffW +: OffW];
  end

  // ---------------------------------------------------------------- prefetch
  // Reads one static word per clock while the queue has room (counting the read in
  // flight), masks it with the offsets that stay inside (own) or reach into (cross) the
  // slab, and queues it.
  // A queue entry, flat (Yosys 0.23 reads packed structs only in some places):
  // {has_cross, has_in, plate, fixed, mass, mask, idx, cross}.
  localparam int ECross = 0, EIdx = 1, EMask = EIdx + SAW, EMass = EMask + Offsets;
  localparam int EFixed = EMass + MassW, EPlate = EFixed + 1, EHasIn = EPlate + 1;
  localparam int EHasCross = EHasIn + 1, ENe = EHasCross + 1, NeW = KW + 1;
  localparam int EntryW = ENe + NeW;  // ENe: the number of edges (ones of the mask)
  logic pf_active_q, pf_cross_q;
  logic [SAW-1:0] pf_idx_q;
  logic rd_q, rd_cross_q;
  // The masked entry, registered before its edges are counted (one clock each).
  logic m1_q;
  logic [EntryW-1:0] m1_e_q;
  logic [SAW-1:0] rd_idx_q;
  // The particle's reach compares, made as it is issued (offsets, count and ghost do not
  // change during a step): own, off < count - idx (the end stays below the slab's end);
  // cross, off >= ghost - idx (the end lies past the ghosts). The read clock's reach
  // selects between them as before, from registers instead of carry chains.
  logic [Offsets-1:0] rd_ge_q, rd_lt_q;
  // The queue: its first entry in a register (head_q), the others in q_mem, so that the
  // slot logic starts from registers.
  logic [EntryW-1:0] q_mem [QDepth];
  logic [QAW-1:0] q_wr_q, q_rd_q;
  logic [QAW:0] q_cnt_q;   // entries in q_mem
  logic [EntryW-1:0] head_q;
  logic head_valid_q;
  logic issue, pop, pf_last;
  assign issue = pf_active_q &&
                 (q_cnt_q + (QAW+1)'(head_valid_q) + (QAW+1)'(rd_q) + (QAW+1)'(m1_q) <
                  (QAW+1)'(QDepth));
  assign pf_last = pf_cross_q ? ({1'b0, pf_idx_q} + 1'b1 == (SAW+1)'(ghost_i))
                              : ({1'b0, pf_idx_q} + 1'b1 == count_i);
  assign own_stat_addr_o = pf_idx_q;
  // The lane below's slab ends at prev_count; its last `ghost` particles are the ghosts.
  assign prev_stat_addr_o = SAW'(prev_count_i - (SAW+1)'(ghost_i) + (SAW+1)'(pf_idx_q));

  logic [StatW-1:0] stat;
  logic [Offsets-1:0] reach, valid_off;
  logic [EntryW-1:0] in_e;
  logic [SAW:0] pf_lim;  // own: count - idx (ends stay below it); cross: ghost - idx
  logic [Offsets-1:0] pf_ge, pf_lt;
  always_comb begin
    pf_lim = pf_cross_q ? (SAW+1)'(ghost_i) - (SAW+1)'(pf_idx_q)
                        : count_i - (SAW+1)'(pf_idx_q);
    for (int k = 0; k < Offsets; k++) begin
      pf_ge[k] = {1'b0, off[k]} >= (OffW+1)'(pf_lim);
      pf_lt[k] = (SAW+1)'(off[k]) < pf_lim;
    end
  end
  always_comb begin
    stat = rd_cross_q ? prev_stat_i : own_stat_i;
    for (int k = 0; k < Offsets; k++) begin
      valid_off[k] = off[k] != '0;
      reach[k] = valid_off[k] && (rd_cross_q ? rd_ge_q[k] : rd_lt_q[k]);
    end
    in_e[ECross] = rd_cross_q;
    in_e[EIdx +: SAW] = rd_idx_q;
    in_e[EMask +: Offsets] = stat[Offsets-1:0] & reach;
    in_e[EMass +: MassW] = stat[rheo_consts_pkg::SweepStaticMassShift +: MassW];
    in_e[EFixed] = stat[rheo_consts_pkg::SweepStaticFixedBit];
    in_e[EPlate] = stat[rheo_consts_pkg::SweepStaticPlateBit];
    in_e[EHasIn] = stat[rheo_consts_pkg::SweepStaticHasInBit];
    in_e[EHasCross] = !rd_cross_q && ((stat[Offsets-1:0] & valid_off & ~reach) != '0);
    in_e[ENe +: NeW] = '0;
  end
  // The queued entry: the masked one with its edges counted.
  logic [EntryW-1:0] q_in;
  always_comb begin
    q_in = m1_e_q;
    q_in[ENe +: NeW] = NeW'($countones(m1_e_q[EMask +: Offsets]));
  end

  // ---------------------------------------------------------------- slots
  // The particle being swept: what is left of its mask and how many slots it has had.
  logic cur_q;
  logic [EntryW-1:0] cur_e_q;
  logic [Offsets-1:0] cur_mask_q;
  logic [CntW-1:0] cur_cnt_q;
  logic [NW:0] n_q;
  logic [DelayW+1:0] wait_q;
  logic waiting_q, running_q, first_pending_q;
  logic [EntryW-1:0] head, e;
  logic [Offsets-1:0] m, m_next;
  logic [NeW-1:0] rem, cur_rem_q;  // edges left of the particle (this slot's included)
  logic [CntW-1:0] cnt;
  logic [KW-1:0] k;
  logic have_head, take, slot, last;
  assign head = head_q;
  assign have_head = head_valid_q;
  logic sweeping;
  assign sweeping = running_q || (waiting_q && wait_q == '0);
  always_comb begin
    take = sweeping && !cur_q && have_head;
    slot = sweeping && (cur_q || have_head);
    e = cur_q ? cur_e_q : head;
    m = cur_q ? cur_mask_q : head[EMask +: Offsets];
    rem = cur_q ? cur_rem_q : head[ENe +: NeW];
    cnt = cur_q ? cur_cnt_q : '0;
    m_next = m & (m - Offsets'(1));
    k = '0;
    for (int i = Offsets - 1; i >= 0; i--)
      if (m[i]) k = KW'(i);
    // From the counters, not the mask: the last slot is decided by small compares.
    last = (rem <= NeW'(1)) &&
           ({1'b0, cnt} + 1'b1 >= (CntW+1)'(e[ECross] ? CrossMin : OwnMin));
  end
  assign pop = take;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      pf_active_q <= 1'b0;
      pf_cross_q <= 1'b0;
      pf_idx_q <= '0;
      rd_q <= 1'b0;
      m1_q <= 1'b0;
      m1_e_q <= '0;
      cur_rem_q <= '0;
      rd_cross_q <= 1'b0;
      rd_idx_q <= '0;
      rd_ge_q <= '0;
      rd_lt_q <= '0;
      q_wr_q <= '0;
      q_rd_q <= '0;
      q_cnt_q <= '0;
      head_q <= '0;
      head_valid_q <= 1'b0;
      cur_q <= 1'b0;
      cur_e_q <= '0;
      cur_mask_q <= '0;
      cur_cnt_q <= '0;
      n_q <= '0;
      wait_q <= '0;
      waiting_q <= 1'b0;
      running_q <= 1'b0;
      first_pending_q <= 1'b0;
      step_first_o <= 1'b0;
      slot_o <= 1'b0;
      edge_o <= 1'b0;
      first_o <= 1'b0;
      last_o <= 1'b0;
      cross_o <= 1'b0;
      idx_o <= '0;
      k_o <= '0;
      n_o <= '0;
      mass_o <= '0;
      fixed_o <= 1'b0;
      plate_o <= 1'b0;
      has_in_o <= 1'b0;
      has_cross_o <= 1'b0;
      starved_o <= 1'b0;
    end else begin
      // Prefetch.
      rd_q <= issue;
      m1_q <= rd_q;
      if (rd_q) m1_e_q <= in_e;
      if (issue) begin
        rd_cross_q <= pf_cross_q;
        rd_idx_q <= pf_idx_q;
        rd_ge_q <= pf_ge;
        rd_lt_q <= pf_lt;
        if (pf_last) begin
          // From the cross sweep to the own sweep, or the end of the lane's particles.
          pf_active_q <= pf_cross_q && count_i != '0;
          pf_cross_q <= 1'b0;
          pf_idx_q <= '0;
        end else begin
          pf_idx_q <= pf_idx_q + 1'b1;
        end
      end
      // The head refills from q_mem, or straight from the read when q_mem is empty.
      if (pop || !head_valid_q) begin
        if (q_cnt_q != '0) begin
          head_q <= q_mem[q_rd_q];
          head_valid_q <= 1'b1;
          q_rd_q <= q_rd_q + 1'b1;
        end else begin
          head_q <= q_in;
          head_valid_q <= m1_q;
        end
      end
      if (m1_q && !((pop || !head_valid_q) && q_cnt_q == '0)) begin
        q_mem[q_wr_q] <= q_in;
        q_wr_q <= q_wr_q + 1'b1;
      end
      q_cnt_q <= q_cnt_q +
                 (QAW+1)'(m1_q && !((pop || !head_valid_q) && q_cnt_q == '0)) -
                 (QAW+1)'((pop || !head_valid_q) && q_cnt_q != '0);
      if (go_i) begin
        pf_active_q <= ghost_i != '0 || count_i != '0;
        pf_cross_q <= ghost_i != '0;
        pf_idx_q <= '0;
        n_q <= '0;
        cur_q <= 1'b0;
        waiting_q <= 1'b1;
        running_q <= 1'b0;
        first_pending_q <= 1'b1;
        // The queue's first entry is there in clock 4 (read, masked, counted); the first
        // slot leaves in clock 4 + delay and is in the slot registers from clock
        // 5 + delay (SweepLeadClocks).
        wait_q <= (DelayW+2)'(delay_i) + (DelayW+2)'(rheo_consts_pkg::SweepLeadClocks - 2);
      end else if (waiting_q) begin
        if (wait_q == '0) begin
          waiting_q <= 1'b0;
          running_q <= 1'b1;
        end else begin
          wait_q <= wait_q - 1'b1;
        end
      end
      // Slots.
      slot_o <= slot;
      step_first_o <= slot && first_pending_q;
      if (slot) first_pending_q <= 1'b0;
      edge_o <= slot && rem != '0;
      first_o <= slot && !cur_q;
      last_o <= slot && last;
      cross_o <= e[ECross];
      idx_o <= e[EIdx +: SAW];
      k_o <= k;
      n_o <= n_q;
      mass_o <= e[EMass +: MassW];
      fixed_o <= e[EFixed];
      plate_o <= e[EPlate];
      has_in_o <= e[EHasIn];
      has_cross_o <= e[EHasCross];
      if (slot) begin
        n_q <= n_q + 1'b1;
        cur_rem_q <= rem - NeW'(rem != '0);
        cur_q <= !last;
        if (take) cur_e_q <= head;
        cur_mask_q <= m_next;
        cur_cnt_q <= cnt + 1'b1;
      end
      // The sweep ends when the prefetch has read every particle and the queue is empty.
      starved_o <= sweeping && !slot && (pf_active_q || rd_q || m1_q);
      if (sweeping && !slot && !pf_active_q && !rd_q && !m1_q) running_q <= 1'b0;
    end
  end
  assign busy_o = waiting_q || running_q;
endmodule
