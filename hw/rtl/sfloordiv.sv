// floor(num / den) for a signed num and den > 0, on udiv: a negative num divides
// -num + den - 1, and the quotient is negated. QS + 1 clocks from start to done for a quotient
// magnitude below 2^QS (QS = qsel ? QB : QA), else W + 1 (udiv).
module sfloordiv #(
    parameter int W  = 64,
    parameter int QA = W,
    parameter int QB = W
) (
    input  logic                clk,
    input  logic                rst,
    input  logic                start,
    input  logic                qsel,
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

  udiv #(.W(W), .QA(QA), .QB(QB)) div (
      .clk(clk), .rst(rst), .start(start && !busy), .qsel(qsel), .num(unum), .den(den),
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
