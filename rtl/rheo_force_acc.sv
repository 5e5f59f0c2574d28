// Force accumulator of one particle bank: a memory of 3-component sums with a
// read-modify-write pipeline (one addition per clock, any address sequence) and a read /
// clear port for the MPM pass. Two memory ports: A reads, B writes (rheo_ram_sdp).
//
// Addition of add_val_i to the sum at add_addr_i:
//   clock 0: read the old sum (port A)
//   clock 1: old sum + value -> register; the old sum is forwarded from the additions in
//            clocks 1 and 2 ahead when they hit the same address (their sums are not yet
//            in the memory when it was read: one is being written now, one was written
//            in the read's own clock and the memory reads first). The address matches are
//            compared in clock 0 and registered, so clock 1 holds only the forwarding mux
//            and the carry chain.
//   clock 2: write the new sum (port B)
// So the same particle may be added in consecutive clocks. Sums wrap in AccW bits: the
// host bounds the degree so that they never do (rheo_consts_pkg::ForceAccW).
// Read / clear (MPM pass, while no additions are in flight): sum_addr_i in clock 0 gives
// sum_o in clock 1; clear_i writes zero at clear_addr_i.
module rheo_force_acc #(
  parameter int AccW = 40,
  parameter int Depth = 256,
  localparam int AddrW = (Depth > 1) ? $clog2(Depth) : 1
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic              add_valid_i,
  input  logic [AddrW-1:0]  add_addr_i,
  input  logic [3*AccW-1:0] add_val_i,
  input  logic [AddrW-1:0]  sum_addr_i,
  output logic [3*AccW-1:0] sum_o,
  input  logic              clear_i,
  input  logic [AddrW-1:0]  clear_addr_i
);
  logic b_valid_q, c_valid_q;
  logic fwd_c_q, fwd_d_q;  // clock 1: forward c_sum_q / d_sum_q (registered address matches)
  logic [AddrW-1:0] b_addr_q, c_addr_q;
  logic [3*AccW-1:0] b_val_q, c_sum_q, d_sum_q;
  logic [3*AccW-1:0] ram_q, old_sum, new_sum;

  rheo_ram_sdp #(.Width(3 * AccW), .Depth(Depth)) u_ram (
    .clk_i   (clk_i),
    .a_addr_i(add_valid_i ? add_addr_i : sum_addr_i),
    .a_data_o(ram_q),
    .b_we_i  (c_valid_q || clear_i),
    .b_addr_i(c_valid_q ? c_addr_q : clear_addr_i),
    .b_data_i(c_valid_q ? c_sum_q : '0)
  );
  assign sum_o = ram_q;

  always_comb begin
    if (fwd_c_q) old_sum = c_sum_q;
    else if (fwd_d_q) old_sum = d_sum_q;
    else old_sum = ram_q;
    for (int i = 0; i < 3; i++)
      new_sum[i*AccW +: AccW] = old_sum[i*AccW +: AccW] + b_val_q[i*AccW +: AccW];
  end

  always_ff @(posedge clk_i) begin
    b_addr_q <= add_addr_i;
    b_val_q <= add_val_i;
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
      // Next clock, b holds add_addr_i, c holds today's b and d today's c.
      fwd_c_q <= b_valid_q && (b_addr_q == add_addr_i);
      fwd_d_q <= c_valid_q && (c_addr_q == add_addr_i);
      b_valid_q <= add_valid_i;
      c_valid_q <= b_valid_q;
    end
  end
endmodule
