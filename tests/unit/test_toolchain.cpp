// The compiler keeps every rounding the source asks for, at every
// optimisation level: a value rounded to float and widened again is the
// rounded value. GCC 12's SLP vectoriser computes float(t - double(float(p)))
// from p instead (at -O2 and up), which made the stress suite's rays, and its
// counts, differ between the Release and the sanitizer (-O1) builds;
// CMakeLists.txt turns it off (-fno-tree-slp-vectorize).
#include <gtest/gtest.h>


namespace {

struct V2 {
    double x, y;
};
struct F2 {
    float x, y;
};

// Compiled on its own (no inlining, no constant propagation into it), as
// the lambda of the stress suite was: two lanes the vectoriser pairs up.
__attribute__((noipa)) void round_then_subtract(const V2& t, const V2& p, F2& o, F2& d) {
    const float ox = float(p.x), oy = float(p.y);
    o = {ox, oy};
    d = {float(t.x - double(ox)), float(t.y - double(oy))};
}

TEST(Toolchain, FloatRoundTripsSurviveVectorisation) {
    // From the closed-mesh stress test: p.x is 3e-8 away from its float.
    const V2 t{-1.0, 1.0}, p{-0x1.03c13937d2d5ep+2, 0x1.2f9bd2103787ap+1};
    F2 o{}, d{};
    round_then_subtract(t, p, o, d);
    EXPECT_EQ(o.x, -0x1.03c13ap+2f);
    EXPECT_EQ(d.x, 0x1.878274p+1f) << std::hexfloat << d.x << " (0x1.878272p+1: the unrounded p was used)";
    EXPECT_EQ(d.y, float(t.y - double(o.y)));
}

}  // namespace
