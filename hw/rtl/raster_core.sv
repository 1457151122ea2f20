// The paper's raster core: one sample's vertices and triangles in, its depth inlier counts out;
// the z-buffer, the box's depth bounds and the transformed vertices in block RAM. Bit-exact with
// the C++ model in src/hw/raster_core.cc (docs/hardware.md gives every signal's width and why it
// suffices); checked by hw/sim. hw/README.md describes the ports.
//
// A sample: pulse `start` with the sample's pose, camera and box held on the inputs until
// `done`. The object vertex distributor then writes items into the core's FIFO while `in_ready`:
// every model vertex (kind 0), then every triangle as three vertex indices (kind 1), then an end
// (kind 2). Each vertex is transformed (three multiply-adds) and projected by three dividers at
// once (IZ, U, V) into the vertex RAM; each triangle reads its three vertices (three clocks), is
// set up in one clock and, when it is drawn, gets its IZ plane from the same dividers and walks
// its bounding box a pixel a clock (two for a covered pixel: read, then compare and write). After
// the end, the core counts the box a pixel a clock, clearing the z-buffer behind it for the next
// sample, and pulses `done` with the counts. The z-buffer is cleared once after reset.
//
// Widths inside the core: IZ < 2^25 + 2 at every vertex and covered pixel (the near plane is at
// least 2048 quarter units), so the z-buffer, the vertex RAM and the bounds keep 26 bits; the
// bounds arrive as the model's 32-bit words and are saturated to 2^26 - 1, which no IZ reaches,
// so every comparison gives the model's answer.
module raster_core #(
    parameter int AW = 13,  // z-buffer and bound words: 2^AW box pixels
    parameter int VW = 11,  // vertex RAM: 2^VW model vertices
    parameter int FD = 5    // the item FIFO: 2^FD items
) (
    input logic clk,
    input logic rst,

    // The depth distributor's port: bounds (lo, hi) of box pixel bnd_addr (row-major).
    input logic          bnd_we,
    input logic [AW-1:0] bnd_addr,
    input logic [  31:0] bnd_lo,
    input logic [  31:0] bnd_hi,

    // The sample: rotation Q1.16 (row-major, 18 bits each), translation (quarter depth units),
    // camera relative to the box corner (hw::Camera), box size in grid pixels, backface culling.
    input logic [9*18-1:0] pose_r,
    input logic [3*32-1:0] pose_t,
    input logic [    31:0] cam_fx,
    input logic [    31:0] cam_fy,
    input logic [    31:0] cam_cx,
    input logic [    31:0] cam_cy,
    input logic [    31:0] cam_z_near,
    input logic [    10:0] box_w,
    input logic [    10:0] box_h,
    input logic            cull,
    input logic            start,

    // Items: kind 0 a vertex (coordinate a at bits [16 a +: 16], quarter depth units), kind 1 a
    // triangle (vertex index k at bits [VW k +: VW]), kind 2 the end of the sample.
    input  logic        in_valid,
    input  logic [ 1:0] in_kind,
    input  logic [47:0] in_data,
    output logic        in_ready,

    output logic        done,
    output logic [31:0] inliers,
    output logic [31:0] rendered,
    output logic [31:0] occluded,
    output logic [31:0] drawn,      // triangles that covered a pixel centre
    output logic [31:0] fragments,  // pixel centres covered

    // Each z-buffer word as the count reads it (for the testbench).
    output logic          cnt_valid,
    output logic [AW-1:0] cnt_addr,
    output logic [  25:0] cnt_z
);
  localparam logic signed [63:0] ONE = 64'sd16;  // a pixel in 1/16 pixel
  localparam logic signed [63:0] BAND = 64'sd16368;  // 1023 pixels
  localparam logic signed [63:0] MAX_SPAN = 64'sd4080;  // 255 pixels
  localparam logic signed [63:0] MAX_IZ = 64'sd67108863;  // 2^26 - 1
  localparam logic [1:0] K_VERTEX = 2'd0, K_TRIANGLE = 2'd1;

  function automatic logic [25:0] sat26(input logic [31:0] x);
    sat26 = (x > 32'd67108863) ? 26'h3ffffff : x[25:0];
  endfunction

  // ---- Memories -------------------------------------------------------------------------
  logic [25:0] zbuf[2**AW];
  logic [51:0] bounds[2**AW];
  logic [AW-1:0] z_raddr, z_waddr, b_raddr;
  logic z_we;
  logic [25:0] z_wdata, z_rdata;
  logic [51:0] b_rdata;
  always_ff @(posedge clk) begin
    if (z_we) zbuf[z_waddr] <= z_wdata;
    z_rdata <= zbuf[z_raddr];
  end
  always_ff @(posedge clk) begin
    if (bnd_we) bounds[bnd_addr] <= {sat26(bnd_hi), sat26(bnd_lo)};
    b_rdata <= bounds[b_raddr];
  end

  // The transformed vertices, 62-bit words (Yosys 0.23 reads no array of structs):
  // {near, in guard band, IZ (26), V (17), U (17)}, U and V box-relative in 1/16 pixel.
  logic [61:0] vram[2**VW];
  logic [VW-1:0] vr_raddr, vr_waddr;
  logic vr_we;
  logic [61:0] vr_wdata, vr_rdata;
  always_ff @(posedge clk) begin
    if (vr_we) vram[vr_waddr] <= vr_wdata;
    vr_rdata <= vram[vr_raddr];
  end

  // The item FIFO (distributed RAM, read combinationally at the head).
  logic [49:0] fifo[2**FD];
  logic [FD:0] f_wr, f_rd;
  logic f_empty, f_pop;
  logic [1:0] h_kind;
  logic [47:0] h_data;
  assign f_empty = f_wr == f_rd;
  assign in_ready = (f_wr - f_rd) != (FD + 1)'(2 ** FD);
  assign {h_kind, h_data} = fifo[f_rd[FD-1:0]];
  always_ff @(posedge clk) begin
    if (rst) f_wr <= '0;
    else if (in_valid && in_ready) begin
      fifo[f_wr[FD-1:0]] <= {in_kind, in_data};
      f_wr <= f_wr + 1'b1;
    end
  end

  // ---- State ----------------------------------------------------------------------------
  typedef enum logic [3:0] {
    S_IDLE, S_CLEAR, S_NEXT, S_XFORM, S_XDIV, S_R1, S_R2, S_SETUP, S_SDIV, S_FILL, S_FILL_WR,
    S_COUNT, S_COUNT_LAST, S_DONE
  } state_t;
  state_t state;

  logic [21:0] pixels;  // box_w * box_h
  assign pixels = box_w * box_h;
  logic [21:0] addr;  // clear and count walk
  logic clean;  // the whole z-buffer is zero (after the first clear, every count leaves it so)
  logic [VW-1:0] vn;  // the next vertex's index
  logic [VW-1:0] i1, i2;  // the triangle's second and third vertex
  logic [61:0] tri_vtx[3];  // the triangle's vertices (the third straight from the RAM)
  logic [61:0] tv0, tv1;
  assign tri_vtx[0] = tv0;
  assign tri_vtx[1] = tv1;
  assign tri_vtx[2] = vr_rdata;

  // ---- Vertex transform -----------------------------------------------------------------
  logic [47:0] tv;  // the vertex's model coordinates
  // X_cam = (R X + 2^15) >> 16 + t: 18 x 16-bit products (one DSP48E2 each), a 36-bit sum.
  logic signed [33:0] cam[3];
  always_comb begin
    for (int r = 0; r < 3; r++) begin
      logic signed [33:0] p0, p1, p2;
      logic signed [35:0] acc;
      p0 = $signed(pose_r[(3 * r) * 18 +: 18]) * $signed(tv[0 +: 16]);
      p1 = $signed(pose_r[(3 * r + 1) * 18 +: 18]) * $signed(tv[16 +: 16]);
      p2 = $signed(pose_r[(3 * r + 2) * 18 +: 18]) * $signed(tv[32 +: 16]);
      acc = 36'(p0) + 36'(p1) + 36'(p2);
      cam[r] = 34'((acc + 36'sd32768) >>> 16) + 34'($signed(pose_t[r * 32 +: 32]));
    end
  end
  logic xnear;
  assign xnear = cam[2] < 34'($signed(cam_z_near));

  // The three dividers of the projection (IZ, U, V), reused for the IZ plane (plane_div). Short
  // paths: IZ < 2^26 always; |U - CX|, |V - CY| < 2^18 for every vertex near the box; the
  // plane's quotients below 2^32 for the triangles of real meshes. Longer quotients take 64
  // clocks, exactly. The three end at different clocks: dd keeps those that have.
  logic div_start, plane_div;
  logic signed [63:0] div_num[3], div_den[3], div_quo[3];
  logic [2:0] div_done, dd;
  logic all_done;
  for (genvar i = 0; i < 3; i++) begin : g_div
    sfloordiv #(.W(64), .QA(i == 0 ? 26 : 18), .QB(32)) d (
        .clk(clk), .rst(rst), .start(div_start), .qsel(plane_div), .num(div_num[i]), .den(div_den[i]),
        /* verilator lint_off PINCONNECTEMPTY */
        .busy(),
        /* verilator lint_on PINCONNECTEMPTY */
        .done(div_done[i]), .quo(div_quo[i])
    );
  end
  assign all_done = (dd | div_done) == 3'b111;

  // The vertex RAM's write: the vertex as its divisions end (or at once when it is near).
  always_comb begin
    logic signed [63:0] u, v;
    u = div_quo[1] + 64'(signed'(cam_cx));
    v = div_quo[2] + 64'(signed'(cam_cy));
    vr_waddr = vn;
    vr_we = (state == S_XFORM && xnear) || (state == S_XDIV && all_done);
    // U and V are kept only in the guard band.
    vr_wdata = {state == S_XFORM, state == S_XDIV && u > -BAND && u < BAND && v > -BAND && v < BAND,
                div_quo[0][25:0], v[16:0], u[16:0]};
  end

  // Per-vertex results of the triangle being set up.
  logic [25:0] viz[3];
  logic [2:0] vnear, vband;

  // ---- Setup (combinational over the three vertices) ------------------------------------
  // Exact for every triangle: the orientation, the bounding box and the verdict (17-bit
  // coordinates in the guard band). Exact for the triangles it passes (a span of at most 255
  // pixels): the edge functions (|E| < 2^25) and the IZ plane, so those products are narrow:
  // 14 x 18 bits for E, 27 x 27 and 18 x 27 bits for the plane.
  logic signed [16:0] X[3], Y[3];
  logic signed [12:0] bw, bh;  // the box size, signed for the comparisons below
  assign bw = {2'b0, box_w};
  assign bh = {2'b0, box_h};
  always_comb for (int k = 0; k < 3; k++) begin
    X[k] = tri_vtx[k][16:0];
    Y[k] = tri_vtx[k][33:17];
    viz[k] = tri_vtx[k][59:34];
    vband[k] = tri_vtx[k][60];
    vnear[k] = tri_vtx[k][61];
  end
  logic signed [35:0] area, neg_area;
  logic signed [17:0] min_x, max_x, min_y, max_y;
  logic [1:0] ib, ic;
  logic signed [17:0] x_lo, x_hi, y_lo, y_hi;
  logic signed [63:0] s_w[3], s_sx[3], s_sy[3];
  logic signed [63:0] plane, plane_x, plane_y;
  logic [3:0] verdict;  // 0: ready, else culled
  always_comb begin
    logic signed [17:0] px0, py0, dx, dy, ax, ay, bx, by, ox, oy;
    logic signed [13:0] dx14, dy14;
    logic signed [35:0] e;
    logic signed [26:0] e27, iz27;
    logic [1:0] e0[3], e1[3], opp[3];
    ax = 18'(X[1]) - 18'(X[0]);
    ay = 18'(Y[1]) - 18'(Y[0]);
    bx = 18'(X[2]) - 18'(X[0]);
    by = 18'(Y[2]) - 18'(Y[0]);
    area = 36'(ax) * 36'(by) - 36'(ay) * 36'(bx);
    ib = (area > 0) ? 2'd2 : 2'd1;
    ic = (area > 0) ? 2'd1 : 2'd2;
    neg_area = (area > 0) ? area : -area;  // -area of the oriented triangle
    min_x = 18'(X[0]); max_x = 18'(X[0]); min_y = 18'(Y[0]); max_y = 18'(Y[0]);
    for (int k = 1; k < 3; k++) begin
      if (18'(X[k]) < min_x) min_x = 18'(X[k]);
      if (18'(X[k]) > max_x) max_x = 18'(X[k]);
      if (18'(Y[k]) < min_y) min_y = 18'(Y[k]);
      if (18'(Y[k]) > max_y) max_y = 18'(Y[k]);
    end
    x_lo = (min_x + 18'sd15) >>> 4; if (x_lo < 0) x_lo = 0;
    x_hi = max_x >>> 4; if (x_hi > 18'(bw) - 1) x_hi = 18'(bw) - 1;
    y_lo = (min_y + 18'sd15) >>> 4; if (y_lo < 0) y_lo = 0;
    y_hi = max_y >>> 4; if (y_hi > 18'(bh) - 1) y_hi = 18'(bh) - 1;
    if (vnear != 3'b000) verdict = 4'd1;
    else if (vband != 3'b111) verdict = 4'd2;
    else if (area == 0) verdict = 4'd3;
    else if (area > 0 && cull) verdict = 4'd4;
    else if (max_x < 0 || min_x > (18'(bw) - 1) * 18'sd16 || max_y < 0 || min_y > (18'(bh) - 1) * 18'sd16)
      verdict = 4'd5;
    else if (max_x - min_x > 18'(MAX_SPAN) || max_y - min_y > 18'(MAX_SPAN)) verdict = 4'd6;
    else if (x_lo > x_hi || y_lo > y_hi) verdict = 4'd7;
    else verdict = 4'd0;
    e0[0] = ic; e0[1] = 2'd0; e0[2] = ib;
    e1[0] = ib; e1[1] = ic; e1[2] = 2'd0;
    opp[0] = 2'd0; opp[1] = ib; opp[2] = ic;
    px0 = x_lo <<< 4;
    py0 = y_lo <<< 4;
    plane = 0; plane_x = 0; plane_y = 0;
    for (int k = 0; k < 3; k++) begin
      dx = 18'(X[e1[k]]) - 18'(X[e0[k]]);
      dy = 18'(Y[e1[k]]) - 18'(Y[e0[k]]);
      dx14 = dx[13:0];
      dy14 = dy[13:0];
      oy = py0 - 18'(Y[e0[k]]);
      ox = px0 - 18'(X[e0[k]]);
      e = 36'(dx14) * 36'(oy) - 36'(dy14) * 36'(ox);
      s_w[k] = 64'(e) - (((dy == 0 && dx < 0) || dy > 0) ? 64'sd0 : 64'sd1);
      s_sx[k] = 64'(dy14) * (-ONE);
      s_sy[k] = 64'(dx14) * ONE;
      e27 = e[26:0];
      iz27 = {1'b0, viz[opp[k]]};
      plane = plane + 64'(e27 * iz27);
      plane_x = plane_x + 64'(18'(s_sx[k]) * iz27);
      plane_y = plane_y + 64'(18'(s_sy[k]) * iz27);
    end
  end

  // ---- Fill registers -------------------------------------------------------------------
  logic signed [63:0] f_w[3], f_wrow[3], f_sx[3], f_sy[3];
  logic signed [63:0] f_iz, f_izrow, f_izsx, f_izsy;
  logic [10:0] f_x, f_y, f_xlo, f_xhi, f_yhi;
  logic [21:0] f_base;  // f_y * box_w
  logic f_covered;
  logic [25:0] f_value;
  logic signed [63:0] f_shifted;
  assign f_covered = !f_w[0][63] && !f_w[1][63] && !f_w[2][63];
  always_comb begin
    f_shifted = f_iz >>> 8;
    if (f_shifted < 1) f_value = 26'd1;
    else if (f_shifted > MAX_IZ) f_value = 26'h3ffffff;
    else f_value = f_shifted[25:0];
  end
  logic f_any;  // the triangle covered a pixel
  logic fill_step;  // this clock leaves the current pixel
  assign fill_step = (state == S_FILL && !f_covered) || state == S_FILL_WR;

  // ---- Count pipeline -------------------------------------------------------------------
  logic c_valid;
  assign cnt_valid = c_valid && (state == S_COUNT || state == S_COUNT_LAST);
  assign cnt_z = z_rdata;

  assign f_pop = state == S_NEXT && !f_empty;

  always_comb begin
    z_raddr = f_base[AW-1:0] + AW'(f_x);
    b_raddr = addr[AW-1:0];
    if (state == S_COUNT) z_raddr = addr[AW-1:0];
    vr_raddr = h_data[0 +: VW];
    if (state == S_R1) vr_raddr = i1;
    if (state == S_R2) vr_raddr = i2;
  end

  always_ff @(posedge clk) begin
    done <= 1'b0;
    z_we <= 1'b0;
    div_start <= 1'b0;
    if (rst) begin
      state <= S_IDLE;
      f_rd <= '0;
      clean <= 1'b0;
    end else begin
      if (f_pop) f_rd <= f_rd + 1'b1;
      dd <= dd | div_done;
      case (state)
        S_IDLE:
        if (start) begin
          addr <= '0;
          vn <= '0;
          inliers <= '0; rendered <= '0; occluded <= '0; drawn <= '0; fragments <= '0;
          state <= clean ? S_NEXT : S_CLEAR;
        end
        S_CLEAR: begin
          z_we <= 1'b1;
          z_waddr <= addr[AW-1:0];
          z_wdata <= '0;
          addr <= addr + 1'b1;
          if (addr == 22'(2 ** AW - 1)) begin
            clean <= 1'b1;
            state <= S_NEXT;
          end
        end
        S_NEXT:
        if (!f_empty) begin
          if (h_kind == K_VERTEX) begin
            tv <= h_data;
            state <= S_XFORM;
          end else if (h_kind == K_TRIANGLE) begin
            // The RAM reads vertex 0 now (vr_raddr), then 1 and 2.
            i1 <= h_data[VW +: VW];
            i2 <= h_data[2 * VW +: VW];
            state <= S_R1;
          end else begin
            addr <= '0;
            c_valid <= 1'b0;
            state <= (pixels == 0) ? S_DONE : S_COUNT;
          end
        end
        S_XFORM: begin
          // Near: written as it is (vr_we); else IZ = 2^36 / Z, U, V = RoundDiv(f X, Z 2^8).
          if (xnear) begin
            vn <= vn + 1'b1;
            state <= S_NEXT;
          end else begin
            plane_div <= 1'b0;
            dd <= '0;
            div_num[0] <= 64'sd68719476736;  // 2^36
            div_den[0] <= 64'(cam[2]);
            // RoundDiv(n, d) = FloorDiv(2 n + d, 2 d), d = Z 2^8: 32 x 34-bit products.
            div_num[1] <= 2 * 64'($signed(cam_fx) * cam[0]) + (64'(cam[2]) <<< 8);
            div_den[1] <= 64'(cam[2]) <<< 9;
            div_num[2] <= 2 * 64'($signed(cam_fy) * cam[1]) + (64'(cam[2]) <<< 8);
            div_den[2] <= 64'(cam[2]) <<< 9;
            div_start <= 1'b1;
            state <= S_XDIV;
          end
        end
        S_XDIV:
        if (all_done) begin
          vn <= vn + 1'b1;
          state <= S_NEXT;
        end
        S_R1: begin
          tv0 <= vr_rdata;
          state <= S_R2;
        end
        S_R2: begin
          tv1 <= vr_rdata;
          state <= S_SETUP;
        end
        S_SETUP: begin
        if (verdict != 4'd0) begin
          state <= S_NEXT;
        end else begin
          for (int k = 0; k < 3; k++) begin
            f_wrow[k] <= s_w[k];
            f_w[k] <= s_w[k];
            f_sx[k] <= s_sx[k];
            f_sy[k] <= s_sy[k];
          end
          f_xlo <= x_lo[10:0];
          f_x <= x_lo[10:0];
          f_xhi <= x_hi[10:0];
          f_y <= y_lo[10:0];
          f_yhi <= y_hi[10:0];
          f_base <= 22'(y_lo[10:0]) * 22'(box_w);
          f_any <= 1'b0;
          plane_div <= 1'b1;
          dd <= '0;
          div_num[0] <= 2 * (plane <<< 8) + 64'(neg_area);
          div_num[1] <= 2 * (plane_x <<< 8) + 64'(neg_area);
          div_num[2] <= 2 * (plane_y <<< 8) + 64'(neg_area);
          div_den[0] <= 2 * 64'(neg_area);
          div_den[1] <= 2 * 64'(neg_area);
          div_den[2] <= 2 * 64'(neg_area);
          div_start <= 1'b1;
          state <= S_SDIV;
        end
        end
        S_SDIV:
        if (all_done) begin
          f_iz <= div_quo[0];
          f_izrow <= div_quo[0];
          f_izsx <= div_quo[1];
          f_izsy <= div_quo[2];
          state <= S_FILL;
        end
        // S_FILL steps past an uncovered pixel, or reads a covered one (z_raddr) and goes to
        // S_FILL_WR, which writes it if nearer and steps (below, fill_step).
        S_FILL: if (f_covered) state <= S_FILL_WR;
        S_FILL_WR: begin
          fragments <= fragments + 1'b1;
          f_any <= 1'b1;
          if (f_value > z_rdata) begin
            z_we <= 1'b1;
            z_waddr <= f_base[AW-1:0] + AW'(f_x);
            z_wdata <= f_value;
          end
        end
        S_COUNT: begin
          // Reads pixel addr now, and zeroes it the clock after; counts the pixel read the
          // clock before.
          z_we <= 1'b1;
          z_waddr <= addr[AW-1:0];
          z_wdata <= '0;
          cnt_addr <= addr[AW-1:0];
          c_valid <= 1'b1;
          addr <= addr + 1'b1;
          if (addr + 1'b1 == pixels) state <= S_COUNT_LAST;
        end
        S_COUNT_LAST: state <= S_DONE;
        S_DONE: begin
          done <= 1'b1;
          state <= S_IDLE;
        end
        default: state <= S_IDLE;
      endcase
      // The next pixel of the triangle's bounding box; after its last, the next item.
      if (fill_step) begin
        state <= S_FILL;
        if (f_x == f_xhi) begin
          if (f_y == f_yhi) begin
            if (f_any || state == S_FILL_WR) drawn <= drawn + 1'b1;
            state <= S_NEXT;
          end
          f_y <= f_y + 1'b1;
          f_x <= f_xlo;
          f_base <= f_base + 22'(box_w);
          for (int k = 0; k < 3; k++) begin
            f_wrow[k] <= f_wrow[k] + f_sy[k];
            f_w[k] <= f_wrow[k] + f_sy[k];
          end
          f_izrow <= f_izrow + f_izsy;
          f_iz <= f_izrow + f_izsy;
        end else begin
          f_x <= f_x + 1'b1;
          for (int k = 0; k < 3; k++) f_w[k] <= f_w[k] + f_sx[k];
          f_iz <= f_iz + f_izsx;
        end
      end
      // The count of the pixel read the clock before (S_COUNT and S_COUNT_LAST).
      if (c_valid && (state == S_COUNT || state == S_COUNT_LAST)) begin
        if (z_rdata != 0) begin
          rendered <= rendered + 1'b1;
          if (b_rdata[25:0] <= z_rdata && z_rdata <= b_rdata[51:26]) inliers <= inliers + 1'b1;
          if (z_rdata < b_rdata[25:0]) occluded <= occluded + 1'b1;
        end
        if (state == S_COUNT_LAST) c_valid <= 1'b0;
      end
    end
  end
endmodule
