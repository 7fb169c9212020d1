#include <gtest/gtest.h>

#include <cmath>

#include "raplas/core/numfmt.hpp"

using raplas::ArithSoft;
using raplas::NumFormat;
using raplas::Rounding;

TEST(NumFormat, ParsesNamesAndRoundTrips) {
    EXPECT_EQ(NumFormat::parse("float32").kind, NumFormat::Kind::f32);
    EXPECT_EQ(NumFormat::parse("float64").kind, NumFormat::Kind::f64);
    NumFormat f = NumFormat::parse("fp1-7-16");
    EXPECT_EQ(f.kind, NumFormat::Kind::custom);
    EXPECT_EQ(f.exp_bits, 7);
    EXPECT_EQ(f.man_bits, 16);
    EXPECT_EQ(f.total_bits(), 24);
    EXPECT_EQ(NumFormat::parse(f.name()), f);
    EXPECT_EQ(NumFormat::parse("fp1-8-15-rtz").rounding, Rounding::toward_zero);
    EXPECT_THROW(NumFormat::parse("fp2-8-15"), std::invalid_argument);
    EXPECT_THROW(NumFormat::parse("fp1-8-15-xyz"), std::invalid_argument);
    EXPECT_THROW(NumFormat::parse("half"), std::invalid_argument);
}

TEST(NumFormat, Fp1_8_23EmulationEqualsHardwareFloat) {
    // The emulated path with float32's widths must reproduce native float
    // arithmetic bit for bit (including ties and the double-rounding cases).
    NumFormat f;
    f.kind = NumFormat::Kind::custom;
    f.exp_bits = 8;
    f.man_bits = 23;
    ArithSoft a{f, true};
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        int e = int((state >> 33) % 40) - 20;
        double m = double((state >> 8) & 0xffffff) / double(1 << 24) + 0.5;
        return double(float(std::ldexp((state & 1) ? m : -m, e)));
    };
    for (int i = 0; i < 200000; ++i) {
        double x = next(), y = next();
        ASSERT_EQ(a.add(x, y), double(float(x) + float(y))) << x << " + " << y;
        ASSERT_EQ(a.mul(x, y), double(float(x) * float(y))) << x << " * " << y;
        ASSERT_EQ(a.div(x, y), double(float(x) / float(y))) << x << " / " << y;
    }
}

TEST(NumFormat, RoundsToNearestEvenAndTowardZero) {
    NumFormat f = NumFormat::parse("fp1-8-2");  // 3 significant bits: 1.00, 1.25, 1.5, 1.75
    EXPECT_EQ(f.round(1.125), 1.0);   // tie -> even
    EXPECT_EQ(f.round(1.375), 1.5);   // tie -> even
    EXPECT_EQ(f.round(1.3), 1.25);
    EXPECT_EQ(f.round(-1.3), -1.25);
    NumFormat z = NumFormat::parse("fp1-8-2-rtz");
    EXPECT_EQ(z.round(1.49), 1.25);
    EXPECT_EQ(z.round(-1.49), -1.25);
    // exact value just below a representable number truncates below it
    EXPECT_EQ(z.round(1.5, -1), 1.25);
    EXPECT_EQ(f.round(1.125, +1), 1.25);  // tie broken by the residual
    EXPECT_TRUE(std::isinf(f.round(1e300)));
    EXPECT_EQ(z.round(1e300), z.max_finite());
}
