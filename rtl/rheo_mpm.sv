// Mass-Point Module: one particle per clock (initiation interval 1). From the particle's
// summed edge force f it integrates semi-implicit Euler in folded units and applies the
// constraints:
//   p += minv f + g;  x += p                     (minv = Fu dt^2 / (m Lu), g in P format)
//   fixed: x = x0, p = 0
//   plate particle above the plate: z = plate_z, p.z = min(p.z, plate_z - z_start),
//     plate_f = f.z  (the held particle moves with the plate, as in the reference model)
//   otherwise below the floor: z = 0, p.z = max(p.z, 0)
// Rounding is to nearest, results saturate and raise sat_o.
// Latency: 5 clocks (input register, minv f, p, x, constraints). Mirrors
// rheo::hls::mpm_particle. Multipliers: 3 (minv f; gravity and dt are folded).
module rheo_mpm #(
  parameter int W = 32,      // state word width (rheo_consts_pkg::Width)
  parameter int CoefW = 24,  // packed coefficient {shift, mantissa}
  parameter int IdxW = 12    // particle index carried alongside
) (
  input  logic            clk_i,
  input  logic            rst_ni,
  input  logic            valid_i,
  input  logic [IdxW-1:0] idx_i,
  input  logic [3*W-1:0]  f_i,         // summed internal force, {z, y, x}
  input  logic [3*W-1:0]  x_i,         // position
  input  logic [3*W-1:0]  p_i,         // displacement per step
  input  logic [3*W-1:0]  x0_i,        // home position (fixed particles)
  input  logic [CoefW-1:0] minv_i,     // packed coefficient Fu dt^2 / (m Lu)
  input  logic [1:0]      flags_i,     // {plate, fixed}
  input  logic [3*W-1:0]  g_i,         // gravity displacement per step^2
  input  logic [W-1:0]    plate_z_i,   // plate height (X format)
  input  logic            plate_en_i,
  input  logic            floor_en_i,
  output logic            valid_o,
  output logic [IdxW-1:0] idx_o,
  output logic [3*W-1:0]  x_o,
  output logic [3*W-1:0]  p_o,
  output logic [W-1:0]    plate_f_o,   // f.z when the plate holds the particle, else 0
  output logic            sat_o
);
  localparam int WideW = rheo_consts_pkg::WideW;
  localparam int FracX = rheo_consts_pkg::FracX;
  localparam int FracP = rheo_consts_pkg::FracP;
  localparam int Last = rheo_consts_pkg::MpmLatency - 1;  // index of the output stage

  if (W != rheo_consts_pkg::Width) begin : g_width_check
    $error("rheo_mpm: W must equal rheo_consts_pkg::Width");
  end

  function automatic logic signed [WideW-1:0] wide(input logic signed [W-1:0] v);
    wide = WideW'(v);
  endfunction

  logic v_q [Last+1];
  logic [IdxW-1:0] idx_q [Last+1];
  logic sat_q [Last+1];
  logic signed [W-1:0] f_q [Last][3];
  logic signed [W-1:0] x_q [Last+1][3];
  logic signed [W-1:0] p_q [Last+1][3];
  logic signed [W-1:0] x0_q [Last][3];
  logic signed [W-1:0] dp_q [3];
  logic [CoefW-1:0] minv_q;
  logic [1:0] flags_q [Last];
  logic signed [W-1:0] plate_f_q;
  logic signed [W-1:0] lim_q;   // (plate_z - z_start) in P format
  logic lim_clip_q;

  logic signed [WideW-1:0] dp_w [3], p1_w [3], p_w [3], x_w [3];
  logic signed [W-1:0] p1 [3];
  logic signed [W-1:0] x_c [3], p_c [3], plate_c;
  logic signed [WideW-1:0] lim_w;
  logic clip1, clip2, clip3, clip4;
  always_comb begin
    clip1 = 1'b0;
    clip2 = 1'b0;
    clip3 = 1'b0;
    for (int i = 0; i < 3; i++) begin
      // stage 1
      dp_w[i] = rheo_consts_pkg::mul_coef_wide(f_q[0][i], minv_q, rheo_consts_pkg::ShiftMinv);
      clip1 = clip1 | rheo_consts_pkg::clips(dp_w[i], W);
      // stage 2
      p1_w[i] = wide(p_q[1][i]) + wide(dp_q[i]);
      p1[i] = rheo_consts_pkg::sat_word(p1_w[i]);
      p_w[i] = wide(p1[i]) + wide(g_i[i*W +: W]);
      clip2 = clip2 | rheo_consts_pkg::clips(p1_w[i], W) | rheo_consts_pkg::clips(p_w[i], W);
      // stage 3
      x_w[i] = wide(x_q[2][i]) + rheo_consts_pkg::round_shift(wide(p_q[2][i]), FracP - FracX);
      clip3 = clip3 | rheo_consts_pkg::clips(x_w[i], W);
    end
    lim_w = rheo_consts_pkg::round_shift(wide(plate_z_i) - wide(x_q[2][2]), -(FracP - FracX));
    clip4 = 1'b0;
    // stage 4: constraints
    for (int i = 0; i < 3; i++) begin
      x_c[i] = x_q[3][i];
      p_c[i] = p_q[3][i];
    end
    plate_c = '0;
    if (flags_q[3][0]) begin
      for (int i = 0; i < 3; i++) begin
        x_c[i] = x0_q[3][i];
        p_c[i] = '0;
      end
    end else if (flags_q[3][1] && plate_en_i && x_q[3][2] > $signed(plate_z_i)) begin
      x_c[2] = plate_z_i;
      if (p_q[3][2] > lim_q) p_c[2] = lim_q;
      plate_c = f_q[3][2];
      clip4 = lim_clip_q;
    end else if (floor_en_i && x_q[3][2] < 0) begin
      x_c[2] = '0;
      if (p_q[3][2] < 0) p_c[2] = '0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      for (int s = 0; s <= Last; s++) v_q[s] <= 1'b0;
    end else begin
      v_q[0] <= valid_i;
      for (int s = 1; s <= Last; s++) v_q[s] <= v_q[s-1];
    end
  end

  always_ff @(posedge clk_i) begin
    idx_q[0] <= idx_i;
    sat_q[0] <= 1'b0;
    for (int i = 0; i < 3; i++) begin
      f_q[0][i] <= f_i[i*W +: W];
      x_q[0][i] <= x_i[i*W +: W];
      p_q[0][i] <= p_i[i*W +: W];
      x0_q[0][i] <= x0_i[i*W +: W];
    end
    minv_q <= minv_i;
    flags_q[0] <= flags_i;
    for (int s = 1; s <= Last; s++) begin
      idx_q[s] <= idx_q[s-1];
      sat_q[s] <= sat_q[s-1];
      x_q[s] <= x_q[s-1];
      p_q[s] <= p_q[s-1];
    end
    for (int s = 1; s < Last; s++) begin
      f_q[s] <= f_q[s-1];
      x0_q[s] <= x0_q[s-1];
      flags_q[s] <= flags_q[s-1];
    end
    // stage 1
    for (int i = 0; i < 3; i++) dp_q[i] <= rheo_consts_pkg::sat_word(dp_w[i]);
    sat_q[1] <= clip1;
    // stage 2
    for (int i = 0; i < 3; i++) p_q[2][i] <= rheo_consts_pkg::sat_word(p_w[i]);
    sat_q[2] <= sat_q[1] | clip2;
    // stage 3
    for (int i = 0; i < 3; i++) x_q[3][i] <= rheo_consts_pkg::sat_word(x_w[i]);
    sat_q[3] <= sat_q[2] | clip3;
    lim_q <= rheo_consts_pkg::sat_word(lim_w);
    lim_clip_q <= rheo_consts_pkg::clips(lim_w, W);
    // stage 4
    for (int i = 0; i < 3; i++) begin
      x_q[4][i] <= x_c[i];
      p_q[4][i] <= p_c[i];
    end
    plate_f_q <= plate_c;
    sat_q[4] <= sat_q[3] | clip4;
  end

  assign valid_o = v_q[Last];
  assign idx_o = idx_q[Last];
  assign x_o = {x_q[Last][2], x_q[Last][1], x_q[Last][0]};
  assign p_o = {p_q[Last][2], p_q[Last][1], p_q[Last][0]};
  assign plate_f_o = plate_f_q;
  assign sat_o = v_q[Last] & sat_q[Last];
endmodule
