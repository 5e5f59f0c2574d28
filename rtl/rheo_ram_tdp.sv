// True dual-port memory (RAMB16 style): port A reads, port B reads or writes, one clock;
// both reads are registered (synchronous) and read-first (a word written in a clock is
// seen by reads from the next clock on).
module rheo_ram_tdp #(
  parameter int Width = 32,
  parameter int Depth = 256,
  localparam int AddrW = (Depth > 1) ? $clog2(Depth) : 1
) (
  input  logic             clk_i,
  input  logic [AddrW-1:0] a_addr_i,
  output logic [Width-1:0] a_data_o,
  input  logic             b_we_i,
  input  logic [AddrW-1:0] b_addr_i,
  input  logic [Width-1:0] b_data_i,
  output logic [Width-1:0] b_data_o
);
  logic [Width-1:0] mem [Depth];
  always_ff @(posedge clk_i) begin
    a_data_o <= mem[a_addr_i];
    b_data_o <= mem[b_addr_i];
    if (b_we_i) mem[b_addr_i] <= b_data_i;
  end
endmodule
