// CORES raster cores working on the samples of one box in lockstep, with the paper's two
// distributors:
//   depth distributor: the box's depth bounds, read once, written to every core (bnd_* port,
//     broadcast to the cores of bnd_cores);
//   object vertex distributor: one triangle stream (the mesh, read once per batch) broadcast to
//     every active core; the stream advances when every active core can take a triangle.
// A batch: `start` with each core's pose (pose_r, pose_t: core c at [c * 162 +: 162] and
// [c * 96 +: 96]), the shared camera and box, and `active` (the cores that hold a sample); the
// triangles; `flush`; `done` when every active core has counted, each core's counts at
// [c * 32 +: 32] of inliers, rendered, occluded.
module raster_top #(
    parameter int CORES = 20,
    parameter int AW = 13
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

    input  logic            tri_valid,
    input  logic [9*16-1:0] tri_v,
    output logic            tri_ready,
    input  logic            flush,

    output logic                  done,
    output logic [CORES*32-1:0] inliers,
    output logic [CORES*32-1:0] rendered,
    output logic [CORES*32-1:0] occluded
);
  logic [CORES-1:0] ready, core_done, finished, batch;
  logic running;

  // Every core of the batch can take the next triangle (or the flush).
  assign tri_ready = running && ((ready | ~batch) == {CORES{1'b1}});

  for (genvar c = 0; c < CORES; c++) begin : g_core
    /* verilator lint_off PINCONNECTEMPTY */
    raster_core #(.AW(AW)) core (
        .clk(clk), .rst(rst),
        .bnd_we(bnd_we && bnd_cores[c]), .bnd_addr(bnd_addr), .bnd_lo(bnd_lo), .bnd_hi(bnd_hi),
        .pose_r(pose_r[c*162 +: 162]), .pose_t(pose_t[c*96 +: 96]),
        .cam_fx(cam_fx), .cam_fy(cam_fy), .cam_cx(cam_cx), .cam_cy(cam_cy), .cam_z_near(cam_z_near),
        .box_w(box_w), .box_h(box_h), .cull(cull),
        .start(start && active[c]),
        .tri_valid(tri_valid && tri_ready && batch[c]), .tri_v(tri_v), .tri_ready(ready[c]),
        .flush(flush && tri_ready && batch[c]),
        .done(core_done[c]),
        .inliers(inliers[c*32 +: 32]), .rendered(rendered[c*32 +: 32]), .occluded(occluded[c*32 +: 32]),
        .drawn(), .fragments(),
        .dbg_addr('0), .dbg_z()
    );
    /* verilator lint_on PINCONNECTEMPTY */
  end

  always_ff @(posedge clk) begin
    done <= 1'b0;
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
        if (flush && tri_ready) running <= 1'b0;
        if (batch != '0) begin
          if ((finished | core_done | ~batch) == {CORES{1'b1}}) begin
            done <= 1'b1;
            batch <= '0;
          end else begin
            finished <= finished | core_done;
          end
        end
      end
    end
  end
endmodule
