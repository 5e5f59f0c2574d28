// Simple dual-port memory: port A reads, port B writes, one clock; the read is registered
// (synchronous), so Yosys maps it to block RAM (RAMB16 on Virtex-II) or LUT RAM. Reading
// the address being written in the same clock returns the old word.
module rheo_ram_sdp #(
  parameter int Width = 32,
  parameter int Depth = 256,
  localparam int AddrW = (Depth > 1) ? $clog2(Depth) : 1
) (
  input  logic             clk_i,
  input  logic [AddrW-1:0] a_addr_i,
  output logic [Width-1:0] a_data_o,
  input  logic             b_we_i,
  input  logic [AddrW-1:0] b_addr_i,
  input  logic [Width-1:0] b_data_i
);
  logic [Width-1:0] mem [Depth];
  always_ff @(posedge clk_i) begin
    a_data_o <= mem[a_addr_i];
    if (b_we_i) mem[b_addr_i] <= b_data_i;
  end
endmodule
