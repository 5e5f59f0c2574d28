// Plate force accumulator of rheo_core: the sum over a step's particles of the force the
// plate exerts (rheo_mpm's plate_f_o), exact in PlateAccW bits; the controller narrows it
// to the step's response word. Kept apart from the controller because it is datapath: a
// wide adder the formal proof does not need to look into.
//
// The lanes' forces of one clock are summed and registered (plate_in_q) before they are
// added to the wide accumulator, and the accumulator is narrowed one clock after its last
// addition, so that no clock holds the lane sum, the wide addition and the saturation
// compare in a row (MpmDrain counts these two clocks).
module rheo_core_plate_acc #(
  parameter int Lanes = 1,
  parameter int W = 32,
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW
) (
  input  logic                 clk_i,
  input  logic                 start_i,  // a step's plate word is taken: clear
  input  logic [Lanes-1:0]     valid_i,
  input  logic [Lanes*W-1:0]   plate_f_i,
  output logic [PlateAccW-1:0] acc_o
);
  localparam int PlateInW = W + $clog2(Lanes + 1);
  logic signed [PlateInW-1:0] plate_in, plate_in_q;
  logic signed [PlateAccW-1:0] plate_acc_q;
  always_comb begin
    plate_in = '0;
    for (int j = 0; j < Lanes; j++) begin
      if (valid_i[j]) plate_in = plate_in + PlateInW'($signed(plate_f_i[j*W +: W]));
    end
  end

  // No asynchronous reset: the accumulator is cleared when a step's plate word arrives, so
  // the clear maps to the flip-flops' synchronous reset instead of a LUT behind the carry
  // chain.
  always_ff @(posedge clk_i) begin
    plate_in_q <= plate_in;
    if (start_i) plate_acc_q <= '0;
    else plate_acc_q <= plate_acc_q + PlateAccW'(plate_in_q);
  end
  assign acc_o = plate_acc_q;
endmodule
