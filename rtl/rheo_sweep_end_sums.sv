// End-side force sums of one sweep lane: a window of Depth three-component sums (address:
// the end particle's local index mod Depth), accumulated read-modify-write at one addition
// per clock, and read by the MPM through a second copy.
//
// Every sum lives only from the first edge into its particle to that particle's MPM (less
// than Depth particles later), so a window replaces a sum per particle, and an addition
// marked first starts its sum afresh: no clearing pass and no stale sum from the previous
// step.
//
// Addition of add_val_i at add_addr_i (rheo_force_acc's pipeline):
//   clock 0: read the old sum (copy A, port A)
//   clock 1: old sum + value -> register; 0 instead of the old sum for a first addition;
//            the old sum forwarded from the additions of clocks 1 and 2 ahead when they hit
//            the same address (not yet in the memory when it was read)
//   clock 2: write the new sum to both copies (port B)
// The MPM reads copy B (port A): sum_addr_i in clock 0 gives sum_o in clock 1. Copy A's
// two ports are busy with the additions in every clock, so the MPM's read needs a copy of
// its own; a word written in clock 2 is read from clock 3 on.
module rheo_sweep_end_sums #(
  parameter int SumW = 36,
  parameter int Depth = 512,
  localparam int AddrW = $clog2(Depth)
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic              add_valid_i,
  input  logic              add_first_i,
  input  logic [AddrW-1:0]  add_addr_i,
  input  logic [3*SumW-1:0] add_val_i,
  input  logic [AddrW-1:0]  sum_addr_i,
  output logic [3*SumW-1:0] sum_o
);
  logic b_valid_q, c_valid_q, b_first_q;
  logic fwd_c_q, fwd_d_q;
  logic [AddrW-1:0] b_addr_q, c_addr_q;
  logic [3*SumW-1:0] b_val_q, c_sum_q, d_sum_q;
  logic [3*SumW-1:0] ram_q, old_sum, new_sum;
  rheo_ram_sdp #(.Width(3 * SumW), .Depth(Depth)) u_copy_a (
    .clk_i(clk_i), .a_addr_i(add_addr_i), .a_data_o(ram_q),
    .b_we_i(c_valid_q), .b_addr_i(c_addr_q), .b_data_i(c_sum_q));
  rheo_ram_sdp #(.Width(3 * SumW), .Depth(Depth)) u_copy_b (
    .clk_i(clk_i), .a_addr_i(sum_addr_i), .a_data_o(sum_o),
    .b_we_i(c_valid_q), .b_addr_i(c_addr_q), .b_data_i(c_sum_q));
  always_comb begin
    if (b_first_q) old_sum = '0;
    else if (fwd_c_q) old_sum = c_sum_q;
    else if (fwd_d_q) old_sum = d_sum_q;
    else old_sum = ram_q;
    for (int i = 0; i < 3; i++)
      new_sum[i*SumW +: SumW] = old_sum[i*SumW +: SumW] + b_val_q[i*SumW +: SumW];
  end
  always_ff @(posedge clk_i) begin
    b_addr_q <= add_addr_i;
    b_val_q <= add_val_i;
    b_first_q <= add_first_i;
    c_addr_q <= b_addr_q;
    c_sum_q <= new_sum;
    d_sum_q <= c_sum_q;
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      b_valid_q <= 1'b0;
      c_valid_q <= 1'b0;
      fwd_c_q <= 1'b0;
      fwd_d_q <= 1'b0;
    end else begin
      fwd_c_q <= b_valid_q && (b_addr_q == add_addr_i);
      fwd_d_q <= c_valid_q && (c_addr_q == add_addr_i);
      b_valid_q <= add_valid_i;
      c_valid_q <= b_valid_q;
    end
  end
endmodule
