// floor(num / den) for a signed num and den > 0, on udiv: a negative num divides
// -num + den - 1, and the quotient is negated. W + 1 cycles from start to done.
module sfloordiv #(
    parameter int W = 64
) (
    input  logic                clk,
    input  logic                rst,
    input  logic                start,
    input  logic signed [W-1:0] num,
    input  logic signed [W-1:0] den,
    output logic                busy,
    output logic                done,
    output logic signed [W-1:0] quo
);
  logic neg, udone, ubusy, pending;
  logic [W-1:0] uquo;
  logic [W-1:0] unum;

  assign unum = num[W-1] ? (-num + den - 1) : num;

  udiv #(.W(W)) div (
      .clk(clk), .rst(rst), .start(start && !busy), .num(unum), .den(den),
      .busy(ubusy), .done(udone), .quo(uquo)
  );

  assign busy = ubusy || pending;

  always_ff @(posedge clk) begin
    done <= 1'b0;
    if (rst) begin
      pending <= 1'b0;
    end else begin
      if (start && !busy) begin
        neg <= num[W-1];
        pending <= 1'b1;
      end
      if (udone) begin
        quo <= neg ? -$signed(uquo) : $signed(uquo);
        done <= 1'b1;
        pending <= 1'b0;
      end
    end
  end
endmodule
