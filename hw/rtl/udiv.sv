// Unsigned division, one quotient bit per clock (restoring): W cycles from start to done.
// quo = floor(num / den) for den > 0 (den = 0 gives all ones, as no caller asks for it).
module udiv #(
    parameter int W = 64
) (
    input  logic         clk,
    input  logic         rst,
    input  logic         start,  // takes num and den; ignored while busy
    input  logic [W-1:0] num,
    input  logic [W-1:0] den,
    output logic         busy,
    output logic         done,   // one clock, quo valid from then until the next start
    output logic [W-1:0] quo
);
  logic [W-1:0] rem;  // < divisor
  logic [W-1:0] shift, divisor;
  logic [$clog2(W+1)-1:0] count;
  logic [W:0] trial;

  assign trial = {rem, shift[W-1]};

  always_ff @(posedge clk) begin
    done <= 1'b0;
    if (rst) begin
      busy <= 1'b0;
    end else if (start && !busy) begin
      busy <= 1'b1;
      rem <= '0;
      shift <= num;
      divisor <= den;
      quo <= '0;
      count <= '0;
    end else if (busy) begin
      if (trial >= {1'b0, divisor}) begin
        rem <= W'(trial - {1'b0, divisor});
        quo <= {quo[W-2:0], 1'b1};
      end else begin
        rem <= trial[W-1:0];
        quo <= {quo[W-2:0], 1'b0};
      end
      shift <= {shift[W-2:0], 1'b0};
      count <= count + 1'b1;
      if (count == W[$clog2(W+1)-1:0] - 1'b1) begin
        busy <= 1'b0;
        done <= 1'b1;
      end
    end
  end
endmodule
