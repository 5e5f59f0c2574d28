// End-particle crossbar of rheo_core: lane j's edge has its start particle in bank j but
// its end particle in any bank, so the end is read (and its force sum updated) through an
// L x L crossbar. The host schedules each edge row so that its ends lie in pairwise
// different banks; this module routes the row and flags a row that breaks that rule.
//
//   stage 1: bank b's port B address is the end local address of the lane whose end lies
//            in bank b; two ends in one bank, or an end bank beyond the lanes, is a
//            schedule conflict.
//   stage 2: lane j's end particle is bank eb2_i[j]'s port B word.
//   results: +F goes to the start sum of the lane's own bank, -F to the end sum of the
//            end's bank (a volume element's result: its own force for each).
// Flat vectors (lane j at [j*n +: n]): Yosys 0.23 mis-connects instance ports to elements
// of two-dimensional unpacked arrays.
module rheo_core_xbar #(
  parameter int Lanes = 1,
  parameter int W = 32,
  parameter int PAW = 8,
  localparam int BW = (Lanes > 1) ? $clog2(Lanes) : 1,
  localparam int EBW = rheo_consts_pkg::EdgeBankBits,
  localparam int AccW = rheo_consts_pkg::ForceAccW,
  localparam int XpW = rheo_consts_pkg::ParticleStateWords * W
) (
  // Stage 1: slot records of the row.
  input  logic [Lanes-1:0]        valid1_i,
  input  logic [Lanes*EBW-1:0]    e_bank1_i,
  input  logic [Lanes*PAW-1:0]    e_local1_i,
  output logic [Lanes*PAW-1:0]    xbar_addr_o,     // per bank
  output logic                    conflict_o,
  // Stage 2: port B words of the banks.
  input  logic [Lanes*XpW-1:0]    xp_b_i,          // per bank
  input  logic [Lanes*BW-1:0]     eb2_i,           // per lane
  output logic [Lanes*XpW-1:0]    end_xp_o,        // per lane
  // TEM results.
  input  logic [Lanes-1:0]        tem_valid_i,
  input  logic [Lanes*3*W-1:0]    tem_f_i,         // added to the start's sum
  input  logic [Lanes-1:0]        tem_elem_i,      // a volume element's result:
  input  logic [Lanes*3*W-1:0]    tem_fe_i,        //   tem_fe_i to the end's sum, else -tem_f_i
  input  logic [Lanes*PAW-1:0]    tem_s_local_i,
  input  logic [Lanes*BW-1:0]     tem_e_bank_i,
  input  logic [Lanes*PAW-1:0]    tem_e_local_i,
  output logic [Lanes-1:0]        acc_s_valid_o,   // per bank
  output logic [Lanes*PAW-1:0]    acc_s_addr_o,
  output logic [Lanes*3*AccW-1:0] acc_s_val_o,
  output logic [Lanes-1:0]        acc_e_valid_o,
  output logic [Lanes*PAW-1:0]    acc_e_addr_o,
  output logic [Lanes*3*AccW-1:0] acc_e_val_o
);
  always_comb begin
    conflict_o = 1'b0;
    for (int b = 0; b < Lanes; b++) begin
      xbar_addr_o[b*PAW +: PAW] = '0;
      for (int j = Lanes - 1; j >= 0; j--) begin
        if (valid1_i[j] && e_bank1_i[j*EBW +: EBW] == EBW'(b))
          xbar_addr_o[b*PAW +: PAW] = e_local1_i[j*PAW +: PAW];
      end
    end
    for (int j = 0; j < Lanes; j++) begin
      if (valid1_i[j] && e_bank1_i[j*EBW +: EBW] >= EBW'(Lanes)) conflict_o = 1'b1;
      for (int k = j + 1; k < Lanes; k++) begin
        if (valid1_i[j] && valid1_i[k] && e_bank1_i[j*EBW +: EBW] == e_bank1_i[k*EBW +: EBW])
          conflict_o = 1'b1;
      end
    end
  end

  // An end bank beyond the lanes (a conflict, already flagged) reads the last bank: with
  // one lane (or a power of two) the mux is then the plain index, no extra logic.
  always_comb begin
    for (int j = 0; j < Lanes; j++) begin
      end_xp_o[j*XpW +: XpW] = xp_b_i[(Lanes-1)*XpW +: XpW];
      for (int b = 0; b < Lanes - 1; b++) begin
        if (eb2_i[j*BW +: BW] == BW'(b)) end_xp_o[j*XpW +: XpW] = xp_b_i[b*XpW +: XpW];
      end
    end
  end

  always_comb begin
    for (int b = 0; b < Lanes; b++) begin
      acc_s_valid_o[b] = tem_valid_i[b];
      acc_s_addr_o[b*PAW +: PAW] = tem_s_local_i[b*PAW +: PAW];
      acc_e_valid_o[b] = 1'b0;
      acc_e_addr_o[b*PAW +: PAW] = '0;
      for (int i = 0; i < 3; i++) begin
        acc_s_val_o[(b*3+i)*AccW +: AccW] = AccW'($signed(tem_f_i[(b*3+i)*W +: W]));
        acc_e_val_o[(b*3+i)*AccW +: AccW] = '0;
      end
      for (int j = Lanes - 1; j >= 0; j--) begin
        if (tem_valid_i[j] && tem_e_bank_i[j*BW +: BW] == BW'(b)) begin
          acc_e_valid_o[b] = 1'b1;
          acc_e_addr_o[b*PAW +: PAW] = tem_e_local_i[j*PAW +: PAW];
          for (int i = 0; i < 3; i++)
            acc_e_val_o[(b*3+i)*AccW +: AccW] =
                tem_elem_i[j] ? AccW'($signed(tem_fe_i[(j*3+i)*W +: W]))
                              : -(AccW'($signed(tem_f_i[(j*3+i)*W +: W])));
        end
      end
    end
  end
endmodule
