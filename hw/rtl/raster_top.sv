// CORES raster cores working on the samples of one box in lockstep, with the paper's two
// distributors:
//   depth distributor: the box's depth bounds, read once, written to every core (bnd_* port,
//     broadcast to the cores of bnd_cores);
//   object vertex distributor: one item stream (the mesh's vertices, then its triangles, read
//     once per batch) broadcast to every active core; the stream advances when every active
//     core's FIFO has room, so the cores run apart by up to a FIFO's depth.
// A batch: `start` with each core's pose (pose_r, pose_t: core c at [c * 162 +: 162] and
// [c * 96 +: 96]), the shared camera and box, and `active` (the cores that hold a sample); the
// items (raster_core's kinds: vertices, triangles, the end); `done` when every active core has
// counted and the weight merger has given each its weight (w_valid, w_core, w_data: a core a
// clock or slower; w_sum: every weight since sum_clear); each core's counts at [c * 32 +: 32] of
// inliers, rendered, occluded. The merger's N_b is the number of box words written with lo > 0
// (an observed depth) since the last write to word 0.
module raster_top #(
    parameter int CORES = 20,
    parameter int AW = 13,
    parameter int VW = 11,
    parameter int FD = 5
) (
    input logic clk,
    input logic rst,

    input logic             bnd_we,
    input logic [CORES-1:0] bnd_cores,
    input logic [   AW-1:0] bnd_addr,
    input logic [     31:0] bnd_lo,
    input logic [     31:0] bnd_hi,

    input logic [CORES*9*18-1:0] pose_r,
    input logic [  CORES*96-1:0] pose_t,
    input logic [          31:0] cam_fx,
    input logic [          31:0] cam_fy,
    input logic [          31:0] cam_cx,
    input logic [          31:0] cam_cy,
    input logic [          31:0] cam_z_near,
    input logic [          10:0] box_w,
    input logic [          10:0] box_h,
    input logic                  cull,
    input logic [     CORES-1:0] active,
    input logic                  start,

    input  logic        in_valid,
    input  logic [ 1:0] in_kind,
    input  logic [47:0] in_data,
    output logic        in_ready,

    // The weight: a, b, c and the box's detector score in Q16.
    input logic [16:0] coef_a,
    input logic [16:0] coef_b,
    input logic [16:0] coef_c,
    input logic [16:0] score,
    input logic        occlusion_aware,
    input logic        sum_clear,
    output logic        w_valid,
    output logic [ 7:0] w_core,
    output logic [31:0] w_data,
    output logic [47:0] w_sum,

    output logic                  done,
    output logic [CORES*32-1:0] inliers,
    output logic [CORES*32-1:0] rendered,
    output logic [CORES*32-1:0] occluded
);
  logic [CORES-1:0] ready, core_done, finished, batch;
  logic running, counted, merged;
  logic [31:0] observed;  // N_b of the box in the cores

  always_ff @(posedge clk) begin
    if (rst) observed <= '0;
    else if (bnd_we) observed <= (bnd_addr == '0 ? 32'd0 : observed) + 32'(bnd_lo != 0);
  end

  weight_merger #(.CORES(CORES)) merger (
      .clk(clk), .rst(rst), .start(counted), .active(active), .inliers(inliers), .rendered(rendered),
      .occluded(occluded), .observed(observed), .coef_a(coef_a), .coef_b(coef_b), .coef_c(coef_c),
      .score(score), .occlusion_aware(occlusion_aware), .sum_clear(sum_clear),
      .w_valid(w_valid), .w_core(w_core), .w_data(w_data), .w_sum(w_sum), .done(merged)
  );
  assign done = merged;

  // Every core of the batch can take the next item.
  assign in_ready = running && ((ready | ~batch) == {CORES{1'b1}});

  for (genvar c = 0; c < CORES; c++) begin : g_core
    /* verilator lint_off PINCONNECTEMPTY */
    raster_core #(.AW(AW), .VW(VW), .FD(FD)) core (
        .clk(clk), .rst(rst),
        .bnd_we(bnd_we && bnd_cores[c]), .bnd_addr(bnd_addr), .bnd_lo(bnd_lo), .bnd_hi(bnd_hi),
        .pose_r(pose_r[c*162 +: 162]), .pose_t(pose_t[c*96 +: 96]),
        .cam_fx(cam_fx), .cam_fy(cam_fy), .cam_cx(cam_cx), .cam_cy(cam_cy), .cam_z_near(cam_z_near),
        .box_w(box_w), .box_h(box_h), .cull(cull),
        .start(start && active[c]),
        .in_valid(in_valid && in_ready && batch[c]), .in_kind(in_kind), .in_data(in_data),
        .in_ready(ready[c]),
        .done(core_done[c]),
        .inliers(inliers[c*32 +: 32]), .rendered(rendered[c*32 +: 32]), .occluded(occluded[c*32 +: 32]),
        .drawn(), .fragments(), .cnt_valid(), .cnt_addr(), .cnt_z()
    );
    /* verilator lint_on PINCONNECTEMPTY */
  end

  always_ff @(posedge clk) begin
    counted <= 1'b0;
    if (rst) begin
      running <= 1'b0;
      batch <= '0;
      finished <= '0;
    end else begin
      if (start) begin
        running <= 1'b1;
        batch <= active;
        finished <= '0;
      end else begin
        if (in_valid && in_ready && in_kind == 2'd2) running <= 1'b0;
        if (batch != '0) begin
          if ((finished | core_done | ~batch) == {CORES{1'b1}}) begin
            counted <= 1'b1;
            batch <= '0;
          end else begin
            finished <= finished | core_done;
          end
        end
      end
    end
  end
endmodule
