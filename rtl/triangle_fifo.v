// Triangle FIFO controller (paper Figure 7): write and read pointers, the
// occupancy, the full and empty flags, and the FIFO's statistics. The
// entries live in a RAM outside this module (the netlist's wrapper models
// it: models/netlist/rtl/triangle_selector_rtl.hpp), written through
// waddr and read from rd_ptr on. A push and the reader's pops take effect at
// the clock edge, pops first; full and empty are judged on the occupancy at
// the start of the cycle (no pass-through of a same-cycle pop,
// docs/MODEL.md §3). `depth` is a configuration input (fifo.triangle_depth).
// FULL_EARLY = 1 builds the deliberately broken variant: full one entry
// early, which the co-simulation check must catch (tests/rtl_cosim.py).
module triangle_fifo #(
    parameter FULL_EARLY = 0
) (
    input  wire        clk,
    input  wire [31:0] depth,      // entries, >= 1
    input  wire        push,       // write one entry at this edge (never when full)
    input  wire [31:0] pop,        // entries the reader takes at this edge (<= count)
    output wire [31:0] waddr,      // RAM address of the next push
    output reg  [31:0] rd_ptr,     // RAM address of the head
    output reg  [31:0] count,      // occupancy
    output wire        full,
    output wire        empty,
    output reg  [63:0] pushes,     // statistics: pushes,
    output reg  [31:0] max_count   // and the largest occupancy after a push
);
    reg  [31:0] wr_ptr;
    wire [31:0] count_after_pop = count - pop;
    wire [31:0] count_next      = count_after_pop + {31'd0, push};
    wire [31:0] rd_sum          = rd_ptr + pop;           // < 2 depth: pop <= count <= depth
    wire [31:0] wr_sum          = wr_ptr + 32'd1;

    initial begin
        wr_ptr    = 32'd0;
        rd_ptr    = 32'd0;
        count     = 32'd0;
        pushes    = 64'd0;
        max_count = 32'd0;
    end

    generate
        if (FULL_EARLY != 0) begin : g_full_early
            assign full = count + 32'd1 >= depth;
        end else begin : g_full
            assign full = count == depth;
        end
    endgenerate
    assign empty = count == 32'd0;
    assign waddr = wr_ptr;

    always @(posedge clk) begin
        rd_ptr <= rd_sum >= depth ? rd_sum - depth : rd_sum;
        count  <= count_next;
        if (push) begin
            wr_ptr <= wr_sum == depth ? 32'd0 : wr_sum;
            pushes <= pushes + 64'd1;
            if (count_next > max_count) max_count <= count_next;
        end
    end
endmodule
