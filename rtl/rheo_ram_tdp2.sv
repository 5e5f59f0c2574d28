// True dual-port memory with a write on either port (RAMB16 style): each port reads or
// writes in a clock, reads are registered (synchronous) and read-first. A word written on
// one port is seen by the other port's reads from the next clock on; the two ports must not
// write one address in the same clock (the users keep them apart).
module rheo_ram_tdp2 #(
  parameter int Width = 32,
  parameter int Depth = 256,
  localparam int AddrW = (Depth > 1) ? $clog2(Depth) : 1
) (
  input  logic             clk_i,
  input  logic             a_we_i,
  input  logic [AddrW-1:0] a_addr_i,
  input  logic [Width-1:0] a_data_i,
  output logic [Width-1:0] a_data_o,
  input  logic             b_we_i,
  input  logic [AddrW-1:0] b_addr_i,
  input  logic [Width-1:0] b_data_i
);
  logic [Width-1:0] mem [Depth];
  always_ff @(posedge clk_i) begin
    a_data_o <= mem[a_addr_i];
    if (a_we_i) mem[a_addr_i] <= a_data_i;
    if (b_we_i) mem[b_addr_i] <= b_data_i;
  end
endmodule
