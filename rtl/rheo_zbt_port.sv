// The core's side of one ZBT SRAM device (IDT71V3556: 128K x 36, pipelined outputs,
// hls/sweep_format.hpp). Every pin is registered here, as the I/O blocks' flip-flops
// would hold it on the board, so the device sees clean edges and its timing adds whole
// clocks:
//   clock c   a command (read or write, address, write data) arrives here
//   clock c+1 address and control on the pins; the device samples them at the next edge
//   clock c+3 write data on the pins (the device's data cycle, ZbtLatency clocks after
//             it sampled the address); read data driven by the device
//   clock c+4 read data in rdata_o
// So a read command's word is in rdata_o ReadLatency = 1 + ZbtLatency + 1 clocks later,
// and a read and a write may follow each other in any order without a dead cycle (the
// data bus carries each command's data ZbtLatency clocks after its address, both ways).
module rheo_zbt_port #(
  localparam int AW = rheo_consts_pkg::ZbtAddrBits,
  localparam int DW = rheo_consts_pkg::ZbtWordBits
) (
  input  logic          clk_i,
  input  logic          rst_ni,
  input  logic          cmd_valid_i,
  input  logic          cmd_we_i,
  input  logic [AW-1:0] cmd_addr_i,
  input  logic [DW-1:0] cmd_wdata_i,
  output logic [DW-1:0] rdata_o,
  // Device pins: CE1# deselects (no operation), R/W# low writes. CEN# and ADV/LD are tied
  // low on the board (every clock counts, every command loads its address).
  output logic [AW-1:0] zbt_a_o,
  output logic          zbt_ce_n_o,
  output logic          zbt_we_n_o,
  output logic [DW-1:0] zbt_d_o,
  output logic          zbt_d_oe_o,   // the core drives the data bus
  input  logic [DW-1:0] zbt_q_i
);
  localparam int Lat = rheo_consts_pkg::ZbtLatency;
  logic [DW-1:0] wdata_q [Lat];
  logic write_q [Lat];
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      zbt_ce_n_o <= 1'b1;
      zbt_we_n_o <= 1'b1;
      zbt_d_oe_o <= 1'b0;
      for (int i = 0; i < Lat; i++) write_q[i] <= 1'b0;
    end else begin
      zbt_ce_n_o <= !cmd_valid_i;
      zbt_we_n_o <= !(cmd_valid_i && cmd_we_i);
      write_q[0] <= cmd_valid_i && cmd_we_i;
      for (int i = 1; i < Lat; i++) write_q[i] <= write_q[i-1];
      zbt_d_oe_o <= write_q[Lat-1];
    end
  end
  always_ff @(posedge clk_i) begin
    zbt_a_o <= cmd_addr_i;
    wdata_q[0] <= cmd_wdata_i;
    for (int i = 1; i < Lat; i++) wdata_q[i] <= wdata_q[i-1];
    zbt_d_o <= wdata_q[Lat-1];
    rdata_o <= zbt_q_i;
  end
endmodule
