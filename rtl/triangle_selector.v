// Triangle Selector with its Triangle FIFO (paper Figure 7, §3.1; the C++
// block: models/triangle_selector.hpp, models/netlist/triangle_selector_module.hpp).
// It watches the Triangle Stream Link and keeps the triangles of the sphere
// at the head of the First-Triangle-ID FIFO, with that sphere's plane masks
// (the PlaneID FIFO's head), in the Triangle FIFO; the rest it discards.
// Combinational: `ready` to the link (the triangle's sphere is decided and,
// under the stall policy, the Triangle FIFO can take it) and `planeid_pop`
// (it takes the last triangle of the head sphere: the PlaneID and
// First-Triangle-ID FIFOs pop at this edge). Registered: the Triangle FIFO
// (triangle_fifo.v) and the counters the model reports.
module triangle_selector #(
    parameter FULL_EARLY = 0              // 1: the broken variant (triangle_fifo.v)
) (
    input  wire        clk,
    // configuration
    input  wire [31:0] depth,             // fifo.triangle_depth
    input  wire        needed_full,       // link.stall_policy = needed_full
    // the ICC's pass state
    input  wire        active,            // the ICC has a group this pass
    input  wire        buf_sel,           // its Ray / Min-distance Memory buffer
    input  wire [31:0] decided,           // spheres the Decoder has decided
    // the Triangle Stream Link
    input  wire        rec_present,
    input  wire [31:0] rec_index,         // the triangle
    input  wire [31:0] rec_sphere,        // its sphere
    input  wire        valid,             // broadcast this cycle
    input  wire        stall,             // offered and held back
    // heads of the First-Triangle-ID and PlaneID FIFOs
    input  wire        ft_valid,          // the First-Triangle-ID FIFO is not empty
    input  wire [31:0] ft_sphere,
    input  wire [31:0] ft_first,
    input  wire [31:0] ft_count,
    input  wire [63:0] pid_rows,
    input  wire [63:0] pid_cols,
    output wire        ready,
    output wire        planeid_pop,
    // the Triangle FIFO: its RAM's write port, and its read side
    output wire        ram_we,
    output wire [31:0] ram_waddr,
    output wire [31:0] ram_wtri,
    output wire        ram_wbuf,
    output wire [63:0] ram_wrows,
    output wire [63:0] ram_wcols,
    input  wire [31:0] pop,               // the Ray Data Fetcher takes this many at this edge
    output wire [31:0] rd_ptr,
    output wire [31:0] count,
    output wire        full,
    output wire        empty,
    // statistics
    output wire [63:0] selected,          // = the Triangle FIFO's pushes
    output wire [31:0] max_count,         // the Triangle FIFO's largest occupancy
    output reg  [63:0] blocked_full,      // cycles it held the link back: Triangle FIFO full
    output reg  [63:0] blocked_undecided  // ... the triangle's sphere not decided yet
);
    // The sphere of the triangle offered (0 when none is, as the model takes it).
    wire [31:0] sphere    = rec_present ? rec_sphere : 32'd0;
    wire        wants     = ft_valid && ft_sphere == sphere;
    wire        undecided = decided <= sphere;
    wire        take      = valid && active && wants;

    assign ready       = !active || (!undecided && (!full || (needed_full && !wants)));
    assign planeid_pop = take && rec_index + 32'd1 == ft_first + ft_count;

    assign ram_we    = take;
    assign ram_wtri  = rec_index;
    assign ram_wbuf  = buf_sel;
    assign ram_wrows = pid_rows;
    assign ram_wcols = pid_cols;

    triangle_fifo #(.FULL_EARLY(FULL_EARLY)) fifo (
        .clk(clk),
        .depth(depth),
        .push(take),
        .pop(pop),
        .waddr(ram_waddr),
        .rd_ptr(rd_ptr),
        .count(count),
        .full(full),
        .empty(empty),
        .pushes(selected),
        .max_count(max_count)
    );

    initial begin
        blocked_full      = 64'd0;
        blocked_undecided = 64'd0;
    end

    always @(posedge clk) begin
        if (!valid && stall && !ready) begin
            if (undecided) blocked_undecided <= blocked_undecided + 64'd1;
            else           blocked_full      <= blocked_full + 64'd1;
        end
    end
endmodule
