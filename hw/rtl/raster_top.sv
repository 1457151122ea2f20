// CORES raster cores, each with a sample of its own box (the boxes of a batch may differ and
// overlap), with the paper's three shared units:
//   depth distributor (depth_distributor.sv): the union of the boxes' observed depth read once,
//     turned into inlier bounds and written to every core whose box holds each pixel;
//   object vertex distributor: one item stream (the mesh's vertices, then its triangles, read
//     once per batch) broadcast to every active core; the stream advances when every active
//     core's FIFO has room, so the cores run apart by up to a FIFO's depth;
//   weight merger (weight_merger.sv): each core's Q16 weight from its counts, and their sum.
// A frame's boxes: `dist_start` with eps and each core's box (box_x0, box_y0 relative to the
// union's corner, box_w, box_h: core c at [11 c +: 11]), then the union's depth while d_ready.
// A batch: `start` with each core's pose (pose_r, pose_t: core c at [c * 162 +: 162] and
// [c * 96 +: 96]) and camera relative to its box (cam_cx, cam_cy at [32 c +: 32]), the shared
// focal lengths and near plane, and `active` (the cores that hold a sample); the items
// (raster_core's kinds: vertices, triangles, the end). When every active core has counted the
// merger gives each its weight (w_valid, w_core, w_data: a core at a time; w_sum: every weight
// since sum_clear); `done` follows the last, each core's counts at [c * 32 +: 32] of inliers,
// rendered, occluded. hw/README.md describes the ports.
module raster_top #(
    parameter int CORES = 20,
    parameter int AW = 13,
    parameter int VW = 11,
    parameter int FD = 5
) (
    input logic clk,
    input logic rst,

    input  logic                dist_start,
    input  logic [        31:0] eps,
    input  logic [CORES*11-1:0] box_x0,
    input  logic [CORES*11-1:0] box_y0,
    input  logic [CORES*11-1:0] box_w,
    input  logic [CORES*11-1:0] box_h,
    input  logic                d_valid,
    input  logic [        10:0] d_x,
    input  logic [        10:0] d_y,
    input  logic [        31:0] d_depth,
    output logic                d_ready,

    input logic [CORES*9*18-1:0] pose_r,
    input logic [  CORES*96-1:0] pose_t,
    input logic [          31:0] cam_fx,
    input logic [          31:0] cam_fy,
    input logic [  CORES*32-1:0] cam_cx,
    input logic [  CORES*32-1:0] cam_cy,
    input logic [          31:0] cam_z_near,
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
  logic [CORES*32-1:0] observed;  // N_b of each core's box
  logic [CORES-1:0] bnd_we;
  logic [CORES*AW-1:0] bnd_addr;
  logic [31:0] bnd_lo, bnd_hi;

  depth_distributor #(.CORES(CORES), .AW(AW)) distributor (
      .clk(clk), .rst(rst), .start(dist_start), .eps(eps), .box_x0(box_x0), .box_y0(box_y0),
      .box_w(box_w), .box_h(box_h), .d_valid(d_valid), .d_x(d_x), .d_y(d_y), .d_depth(d_depth),
      .d_ready(d_ready), .bnd_we(bnd_we), .bnd_addr(bnd_addr), .bnd_lo(bnd_lo), .bnd_hi(bnd_hi),
      .observed(observed)
  );

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
        .bnd_we(bnd_we[c]), .bnd_addr(bnd_addr[c*AW +: AW]), .bnd_lo(bnd_lo), .bnd_hi(bnd_hi),
        .pose_r(pose_r[c*162 +: 162]), .pose_t(pose_t[c*96 +: 96]),
        .cam_fx(cam_fx), .cam_fy(cam_fy), .cam_cx(cam_cx[c*32 +: 32]), .cam_cy(cam_cy[c*32 +: 32]),
        .cam_z_near(cam_z_near), .box_w(box_w[c*11 +: 11]), .box_h(box_h[c*11 +: 11]), .cull(cull),
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
