// Plate force accumulator of the sweep core: the sum over a step's particles of the force
// the plate exerts (each lane's rheo_mpm plate_f_o), exact in PlateAccW bits, like
// rheo_core_plate_acc, but with the lanes' forces summed in a registered tree of pair sums
// (SweepPlateTreeLevels levels for up to 2^levels lanes): with five lanes a single clock of
// four chained additions would set the core's clock. The tree's depth is fixed, so a
// step's clocks do not depend on the lane count (hls::kSweepDrainCycles counts it).
module rheo_sweep_plate_acc #(
  parameter int Lanes = 5,
  parameter int W = 32,
  localparam int Levels = rheo_consts_pkg::SweepPlateTreeLevels,
  localparam int Leaves = 1 << Levels,
  localparam int PlateAccW = rheo_consts_pkg::PlateAccW
) (
  input  logic                 clk_i,
  input  logic                 start_i,  // clear: a step's force latched, or a step starts alone
  input  logic [Lanes-1:0]     valid_i,
  input  logic [Lanes*W-1:0]   plate_f_i,
  output logic [PlateAccW-1:0] acc_o
);
  localparam int TreeW = W + Levels;  // a sum of Leaves words
  if (Lanes > Leaves) begin : g_lanes_check
    $error("rheo_sweep_plate_acc: more lanes than the tree has leaves");
  end
  // The leaves: each lane's force when it has one, 0 for the missing lanes.
  logic signed [TreeW-1:0] leaf [Leaves];
  for (genvar j = 0; j < Leaves; j++) begin : g_leaf
    if (j < Lanes) begin : g_lane
      assign leaf[j] = valid_i[j] ? TreeW'($signed(plate_f_i[j*W +: W])) : TreeW'(0);
    end else begin : g_none
      assign leaf[j] = '0;
    end
  end
  // Three levels of registered pair sums (SweepPlateTreeLevels = 3: up to eight lanes).
  if (Levels != 3) begin : g_levels_check
    $error("rheo_sweep_plate_acc: the tree below has three levels");
  end
  logic signed [TreeW-1:0] sum1_q [4], sum2_q [2], sum3_q;
  always_ff @(posedge clk_i) begin
    for (int j = 0; j < 4; j++) sum1_q[j] <= leaf[2*j] + leaf[2*j+1];
    for (int j = 0; j < 2; j++) sum2_q[j] <= sum1_q[2*j] + sum1_q[2*j+1];
    sum3_q <= sum2_q[0] + sum2_q[1];
  end
  // Cleared when a step's force is latched or a step starts alone (a synchronous reset, as
  // rheo_core's); a step gone ahead adds nothing before the last one's force is latched.
  logic signed [PlateAccW-1:0] plate_acc_q;
  always_ff @(posedge clk_i) begin
    if (start_i) plate_acc_q <= '0;
    else plate_acc_q <= plate_acc_q + PlateAccW'(sum3_q);
  end
  assign acc_o = plate_acc_q;
endmodule
