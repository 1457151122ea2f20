// The paper's weight merger: after a batch, each active core's weight from its counts,
// w = floor(a N / N_b) + floor(b N / N_r) + floor(c s / 2^16) in Q16, exactly as hw::MergedWeight
// (src/hw/weight_merger.cc); N_r leaves out the hidden pixels with `occlusion_aware`. Two
// dividers (the recall and precision terms at once), 18-bit short paths (N <= N_b and N <= N_r
// give quotients <= 2^16): about 21 clocks a core. `w_sum` adds up every weight since `sum_clear`
// (the filter's mean weight and its resampling table need it).
module weight_merger #(
    parameter int CORES = 20
) (
    input logic clk,
    input logic rst,

    input logic                  start,  // one clock; the inputs below hold until done
    input logic [   CORES-1:0]   active,
    input logic [CORES*32-1:0]   inliers,
    input logic [CORES*32-1:0]   rendered,
    input logic [CORES*32-1:0]   occluded,
    input logic [CORES*32-1:0]   observed,  // N_b of each core's box
    input logic [        16:0]   coef_a,    // Q16, each at most 2^16
    input logic [        16:0]   coef_b,
    input logic [        16:0]   coef_c,
    input logic [        16:0]   score,
    input logic                  occlusion_aware,
    input logic                  sum_clear,

    output logic        w_valid,  // one clock a core: core w_core's weight is w_data
    output logic [ 7:0] w_core,
    output logic [31:0] w_data,
    output logic [47:0] w_sum,
    output logic        done      // one clock, after the last active core's weight
);
  localparam int CI = $clog2(CORES + 1);
  typedef enum logic [1:0] {M_IDLE, M_NEXT, M_DIV} mstate_t;
  mstate_t state;
  logic [CI-1:0] core;
  logic [31:0] n, r, nb;
  logic [33:0] detector;  // floor(c s / 2^16)
  logic div_start;
  logic [63:0] quo_recall, quo_precision;
  logic [1:0] div_done, dd;

  always_comb begin
    n = inliers[core * 32 +: 32];
    nb = observed[core * 32 +: 32];
    r = occlusion_aware ? rendered[core * 32 +: 32] - occluded[core * 32 +: 32] : rendered[core * 32 +: 32];
  end
  logic [63:0] num_a, num_b;
  assign num_a = 64'(coef_a) * 64'(n);
  assign num_b = 64'(coef_b) * 64'(n);

  udiv #(.W(64), .QA(18), .QB(18)) recall_div (
      .clk(clk), .rst(rst), .start(div_start), .qsel(1'b0), .num(num_a), .den(64'(nb)),
      /* verilator lint_off PINCONNECTEMPTY */
      .busy(),
      /* verilator lint_on PINCONNECTEMPTY */
      .done(div_done[0]), .quo(quo_recall)
  );
  udiv #(.W(64), .QA(18), .QB(18)) precision_div (
      .clk(clk), .rst(rst), .start(div_start), .qsel(1'b0), .num(num_b), .den(64'(r)),
      /* verilator lint_off PINCONNECTEMPTY */
      .busy(),
      /* verilator lint_on PINCONNECTEMPTY */
      .done(div_done[1]), .quo(quo_precision)
  );

  always_ff @(posedge clk) begin
    w_valid <= 1'b0;
    done <= 1'b0;
    div_start <= 1'b0;
    if (rst) begin
      state <= M_IDLE;
      w_sum <= '0;
    end else begin
      if (sum_clear) w_sum <= '0;
      dd <= dd | div_done;
      case (state)
        M_IDLE:
        if (start) begin
          core <= '0;
          detector <= (34'(coef_c) * 34'(score)) >> 16;
          state <= M_NEXT;
        end
        M_NEXT:
        if (core == CI'(CORES)) begin
          done <= 1'b1;
          state <= M_IDLE;
        end else if (!active[core]) begin
          core <= core + 1'b1;
        end else begin
          dd <= '0;
          div_start <= 1'b1;
          state <= M_DIV;
        end
        M_DIV:
        if ((dd | div_done) == 2'b11) begin
          logic [31:0] w;  // as the model's, modulo 2^32 (never reached: w <= 2^16 + 2^16 + 2^16)
          w = 32'((nb != 0 ? quo_recall : 64'd0) + ($signed(r) > 0 ? quo_precision : 64'd0) + 64'(detector));
          w_valid <= 1'b1;
          w_core <= 8'(core);
          w_data <= w;
          w_sum <= w_sum + 48'(w);
          core <= core + 1'b1;
          state <= M_NEXT;
        end
        default: state <= M_IDLE;
      endcase
    end
  end
endmodule
