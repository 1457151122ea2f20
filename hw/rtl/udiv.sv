// Unsigned division, one quotient bit per clock (restoring), quo = floor(num / den) for den > 0
// (den = 0 gives all ones, as no caller asks for it).
// A quotient below 2^QS (num >> QS < den, checked at start) takes QS clocks from start to done:
// the top W - QS bits of num are the first partial remainder, as the W - QS quotient bits they
// would give are zero. Any other quotient takes W clocks. Exact either way. QS is QA, or QB
// where `qsel` is set at start (two constant shifts and a multiplexer).
module udiv #(
    parameter int W  = 64,
    parameter int QA = W,  // the short paths' quotient bits, 1..W
    parameter int QB = W
) (
    input  logic         clk,
    input  logic         rst,
    input  logic         start,  // takes num, den and qsel; ignored while busy
    input  logic         qsel,
    input  logic [W-1:0] num,
    input  logic [W-1:0] den,
    output logic         busy,
    output logic         done,   // one clock, quo valid from then until the next start
    output logic [W-1:0] quo
);
  localparam int CW = $clog2(W + 1);
  logic [W-1:0] rem;  // < divisor
  logic [W-1:0] shift, divisor;
  logic [CW-1:0] count, last;
  logic [W:0] trial;
  logic [W-1:0] head, tail;
  logic [CW-1:0] qs_last;

  assign trial = {rem, shift[W-1]};
  assign head = qsel ? num >> QB : num >> QA;
  assign tail = qsel ? num << (W - QB) : num << (W - QA);
  assign qs_last = qsel ? CW'(QB - 1) : CW'(QA - 1);

  always_ff @(posedge clk) begin
    done <= 1'b0;
    if (rst) begin
      busy <= 1'b0;
    end else if (start && !busy) begin
      busy <= 1'b1;
      if (head < den) begin
        rem <= head;
        shift <= tail;
        last <= qs_last;
      end else begin
        rem <= '0;
        shift <= num;
        last <= CW'(W - 1);
      end
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
      if (count == last) begin
        busy <= 1'b0;
        done <= 1'b1;
      end
    end
  end
endmodule
