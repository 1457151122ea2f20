// The paper's depth distributor: the observed depth of the union of a batch's boxes read once,
// pixel by pixel in raster order, turned into the inlier bounds of hw::InlierBounds
// (src/hw/raster_core.cc) and written to every core whose box holds the pixel, at that core's
// own box-relative address. Boxes may overlap and differ from core to core; they lie on one
// grid (the stream's). Per core it also counts N_b, the box's pixels with an observed depth.
//
// A batch: `start` with eps and each core's box (grid pixels relative to the stream's first
// pixel; core c's at [11 c +: 11] of box_x0, box_y0, box_w, box_h); then the union's pixels
// (d_x, d_y: grid pixel, d_depth: depth units, 0 = none) while d_ready. A pixel without depth
// takes a clock; one with depth two dividers at once, lo = floor(2^34 / (d + eps)) + 1 and
// hi = ceil(2^34 / (d - eps)) - 1 (2^32 - 1 when d <= eps), 26-bit short paths (d + eps >= 256
// depth units, 2.56 cm): about 28 clocks.
module depth_distributor #(
    parameter int CORES = 20,
    parameter int AW = 13
) (
    input logic clk,
    input logic rst,

    input logic                start,
    input logic [        31:0] eps,  // depth units, >= 1
    input logic [CORES*11-1:0] box_x0,
    input logic [CORES*11-1:0] box_y0,
    input logic [CORES*11-1:0] box_w,
    input logic [CORES*11-1:0] box_h,

    input  logic        d_valid,
    input  logic [10:0] d_x,
    input  logic [10:0] d_y,
    input  logic [31:0] d_depth,
    output logic        d_ready,

    output logic [   CORES-1:0] bnd_we,
    output logic [CORES*AW-1:0] bnd_addr,
    output logic [        31:0] bnd_lo,
    output logic [        31:0] bnd_hi,
    output logic [CORES*32-1:0] observed  // N_b per core since start
);
  localparam logic [63:0] TWO34 = 64'd17179869184;
  localparam logic [63:0] MAX32 = 64'hffffffff;

  typedef enum logic [1:0] {D_IDLE, D_DIV, D_WRITE} dstate_t;
  dstate_t state;
  logic [10:0] px, py;
  logic [31:0] d;
  logic [AW-1:0] next_addr[CORES];  // each core's next box word
  logic [31:0] lo, hi;

  logic div_start;
  logic [63:0] q_lo, q_hi;
  logic [1:0] div_done, dd;
  logic [63:0] den_lo, den_hi;
  assign den_lo = 64'(d) + 64'(eps);
  assign den_hi = 64'(d) - 64'(eps);
  udiv #(.W(64), .QA(26), .QB(26)) lo_div (
      .clk(clk), .rst(rst), .start(div_start), .qsel(1'b0), .num(TWO34), .den(den_lo),
      /* verilator lint_off PINCONNECTEMPTY */
      .busy(),
      /* verilator lint_on PINCONNECTEMPTY */
      .done(div_done[0]), .quo(q_lo)
  );
  // Only its quotient with d > eps is used (den_hi > 0 then).
  udiv #(.W(64), .QA(26), .QB(26)) hi_div (
      .clk(clk), .rst(rst), .start(div_start), .qsel(1'b0), .num(TWO34 + den_hi - 64'd1), .den(den_hi),
      /* verilator lint_off PINCONNECTEMPTY */
      .busy(),
      /* verilator lint_on PINCONNECTEMPTY */
      .done(div_done[1]), .quo(q_hi)
  );

  assign d_ready = state == D_IDLE;

  always_ff @(posedge clk) begin
    bnd_we <= '0;
    div_start <= 1'b0;
    if (rst) begin
      state <= D_IDLE;
    end else begin
      dd <= dd | div_done;
      case (state)
        D_IDLE:
        if (start) begin
          for (int c = 0; c < CORES; c++) begin
            next_addr[c] <= '0;
            observed[c * 32 +: 32] <= '0;
          end
        end else if (d_valid) begin
          px <= d_x;
          py <= d_y;
          d <= d_depth;
          if (d_depth == 0) begin
            lo <= '0;
            hi <= '0;
            state <= D_WRITE;
          end else begin
            dd <= '0;
            div_start <= 1'b1;
            state <= D_DIV;
          end
        end
        D_DIV:
        if ((dd | div_done) == 2'b11) begin
          logic [63:0] l, h;
          l = q_lo + 64'd1;
          h = d > eps ? q_hi - 64'd1 : MAX32;
          lo <= l > MAX32 ? 32'hffffffff : l[31:0];
          hi <= h > MAX32 ? 32'hffffffff : h[31:0];
          state <= D_WRITE;
        end
        D_WRITE: begin
          // Every core whose box holds the pixel takes it at its next word.
          for (int c = 0; c < CORES; c++) begin
            logic [10:0] x0, y0, w, h;
            x0 = box_x0[c * 11 +: 11];
            y0 = box_y0[c * 11 +: 11];
            w = box_w[c * 11 +: 11];
            h = box_h[c * 11 +: 11];
            if (px >= x0 && 12'(px) < 12'(x0) + 12'(w) && py >= y0 && 12'(py) < 12'(y0) + 12'(h)) begin
              bnd_we[c] <= 1'b1;
              bnd_addr[c * AW +: AW] <= next_addr[c];
              next_addr[c] <= next_addr[c] + 1'b1;
              observed[c * 32 +: 32] <= observed[c * 32 +: 32] + 32'(lo != 0);
            end
          end
          bnd_lo <= lo;
          bnd_hi <= hi;
          state <= D_IDLE;
        end
        default: state <= D_IDLE;
      endcase
    end
  end
endmodule
