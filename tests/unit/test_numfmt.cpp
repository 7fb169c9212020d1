#include <gtest/gtest.h>

#include <cfenv>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#include "raplas/core/intersect.hpp"
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

namespace {

// Random floats over the whole float32 range (normal and subnormal), with
// values of few significant bits now and then so that ties and exact
// power-of-two results occur.
struct FloatGen {
    std::uint64_t state;
    explicit FloatGen(std::uint64_t seed) : state(seed) {}
    std::uint64_t bits() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return state >> 11;
    }
    double next() {
        const std::uint64_t r = bits();
        const int kind = int(r % 8);
        int e;
        if (kind == 0) e = int((r >> 3) % 300) - 160;  // anywhere, including under- and overflow
        else e = int((r >> 3) % 40) - 20;
        double m = double((r >> 12) & 0xffffff) / double(1 << 24) + 0.5;
        if (kind == 1) m = 0.5;                                           // powers of two
        if (kind == 2) m = double((r >> 12) & 0xf) / 32.0 + 0.5;           // few bits
        return double(float(std::ldexp((r >> 40) & 1 ? m : -m, e)));
    }
};

}  // namespace

// The x86 float unit in the given rounding mode is the reference for the
// emulated fp1-8-23 formats: every add, sub, mul and div, including results
// that land on (or just below) a power of two, overflow and underflow.
void expect_emulation_equals_hardware(const char* format, int fe_mode, std::uint64_t seed) {
    ArithSoft a{NumFormat::parse(format), true};
    ASSERT_EQ(a.f.kind, NumFormat::Kind::custom);
    FloatGen g(seed);
    constexpr int kN = 100000;
    std::vector<float> x(kN), y(kN), s(kN), d(kN), p(kN), q(kN);
    for (int i = 0; i < kN; ++i) {
        x[i] = float(g.next());
        y[i] = float(g.next());
    }
    const int old = std::fegetround();
    ASSERT_EQ(std::fesetround(fe_mode), 0);
    for (int i = 0; i < kN; ++i) {
        volatile float vx = x[i], vy = y[i];
        s[i] = vx + vy;
        d[i] = vx - vy;
        p[i] = vx * vy;
        q[i] = vx / vy;
    }
    std::fesetround(old);
    // same value and sign (zeros), or both NaN
    auto same = [](double u, float v) {
        return (std::isnan(u) && std::isnan(v)) || (u == double(v) && std::signbit(u) == std::signbit(v));
    };
    int zero_or_special = 0;
    for (int i = 0; i < kN; ++i) {
        ASSERT_PRED2(same, a.add(x[i], y[i]), s[i]) << format << ": " << x[i] << " + " << y[i];
        ASSERT_PRED2(same, a.sub(x[i], y[i]), d[i]) << format << ": " << x[i] << " - " << y[i];
        ASSERT_PRED2(same, a.mul(x[i], y[i]), p[i]) << format << ": " << x[i] << " * " << y[i];
        ASSERT_PRED2(same, a.div(x[i], y[i]), q[i]) << format << ": " << x[i] << " / " << y[i];
        zero_or_special += p[i] == 0 || std::fabs(p[i]) >= FLT_MAX || std::fpclassify(p[i]) == FP_SUBNORMAL;
    }
    EXPECT_GT(zero_or_special, 100);  // the range edges were exercised
}

TEST(NumFormat, Fp1_8_23EmulationEqualsHardwareFloatOverTheWholeRange) {
    // -psiunnorm selects the emulated path; add() itself still normalises
    expect_emulation_equals_hardware("fp1-8-23-psiunnorm", FE_TONEAREST, 98);
}

TEST(NumFormat, Fp1_8_23RtzEmulationEqualsHardwareFloatRoundingTowardZero) {
    expect_emulation_equals_hardware("fp1-8-23-rtz", FE_TOWARDZERO, 99);
}

TEST(NumFormat, TowardZeroJustBelowAPowerOfTwoStaysInTheBinadeBelow) {
    // 1 - 2^-60 rounds to 1.0 in double; toward zero in 3 significant bits it
    // is 0.875, the largest value below 1 (not 0.75, one quantum of [1, 2) below).
    ArithSoft z{NumFormat::parse("fp1-8-2-rtz"), true};
    EXPECT_EQ(z.add(1.0, -std::ldexp(1.0, -60)), 0.875);
    EXPECT_EQ(z.add(-1.0, std::ldexp(1.0, -60)), -0.875);
    EXPECT_EQ(z.f.round(1.0, -1), 0.875);
    EXPECT_EQ(z.f.round(4.0, -1), 3.5);
    EXPECT_EQ(z.f.round(1.0, +1), 1.0);
    ArithSoft n{NumFormat::parse("fp1-8-2"), true};
    EXPECT_EQ(n.add(1.0, -std::ldexp(1.0, -60)), 1.0);
}

TEST(NumFormat, PsiUnnormalizedSuffixParsesAndSwitches) {
    NumFormat f = NumFormat::parse("fp1-7-16-rtz-psiunnorm");
    EXPECT_FALSE(f.psi_normalize);
    EXPECT_EQ(f.rounding, Rounding::toward_zero);
    EXPECT_EQ(f.name(), "fp1-7-16-rtz-psiunnorm");
    EXPECT_EQ(NumFormat::parse(f.name()), f);
    EXPECT_FALSE(f == NumFormat::parse("fp1-7-16-rtz"));
    // float32's widths without PSI normalisation run emulated
    NumFormat g = NumFormat::parse("fp1-8-23-psiunnorm");
    EXPECT_EQ(g.kind, NumFormat::Kind::custom);
    NumFormat h = NumFormat::float32();
    h.set_psi_normalize(false);
    EXPECT_EQ(h, g);
    h.set_psi_normalize(true);
    EXPECT_EQ(h, NumFormat::float32());
    NumFormat d = NumFormat::float64();
    EXPECT_THROW(d.set_psi_normalize(false), std::invalid_argument);
    EXPECT_THROW(NumFormat::parse("fp1-7-16-psi"), std::invalid_argument);
}

TEST(NumFormat, UnnormalizedAdderKeepsTheExponentAfterCancellation) {
    // fp1-8-4: 5 significant bits. Hand-computed: with a stored exponent E the
    // result is a multiple of 2^(E-4).
    ArithSoft a{NumFormat::parse("fp1-8-4-psiunnorm"), true};
    ArithSoft z{NumFormat::parse("fp1-8-4-rtz-psiunnorm"), true};
    ArithSoft norm{NumFormat::parse("fp1-8-4"), true};
    const double small = 0.01171875;  // 3/256 = 1.1b x 2^-7
    {
        // 1.0625 - 1 = 0.0625 keeps E = 0 (quantum 1/16); + 3/256 = 0.07421875
        // -> 1.1875 quanta -> 1 quantum: 0.0625. Normalised: 19/256 exactly.
        const double t[3] = {1.0625, -1.0, small};
        EXPECT_EQ(a.sum_unnormalized(t, 3), 0.0625);
        EXPECT_EQ(z.sum_unnormalized(t, 3), 0.0625);
        EXPECT_EQ(norm.add(norm.add(1.0625, -1.0), small), 0.07421875);
        // one add at a time, each operand taken as normalised, is the
        // normalised result here: the stored exponent is what differs
        ArithSoft per_op{NumFormat::parse("fp1-8-4"), false};
        EXPECT_EQ(per_op.add(per_op.add(1.0625, -1.0), small), 0.07421875);
    }
    {
        // 1.5 - 1.5 = 0 with E = 0: 3/256 rounds to 0 at quantum 1/16,
        // and 0.03125 (= 0.5 quantum, a tie) rounds to even, 0.
        const double t[3] = {1.5, -1.5, small};
        EXPECT_EQ(a.sum_unnormalized(t, 3), 0.0);
        const double u[3] = {1.5, -1.5, 0.03125};
        EXPECT_EQ(a.sum_unnormalized(u, 3), 0.0);
        const double v[3] = {1.5, -1.5, 0.09375};  // 1.5 quanta: tie -> 2 quanta
        EXPECT_EQ(a.sum_unnormalized(v, 3), 0.125);
        EXPECT_EQ(z.sum_unnormalized(v, 3), 0.0625);  // truncated
    }
    {
        // carry out: 1.9375 + 0.125 = 2.0625 -> E = 1, quantum 1/8: 16.5 -> 16 (tie to even)
        const double t[2] = {1.9375, 0.125};
        EXPECT_EQ(a.sum_unnormalized(t, 2), 2.0);
        // 1.9375 + 0.09375 = 2.03125 -> 16.25 quanta -> 2.0; then + 0.0625 at E = 1
        // (quantum 1/8): 2.0625 -> tie -> 2.0; normalised the same here
        const double u[3] = {1.9375, 0.09375, 0.0625};
        EXPECT_EQ(a.sum_unnormalized(u, 3), 2.0);
        // rounding up into the next binade: 1.9375 + 0.046875 = 1.984375 ->
        // 31.75 quanta of 1/16 -> 32 -> 2.0 with E = 1; + 0.0625 -> 2.0625 at
        // quantum 1/8 -> tie -> 2.0
        const double w[3] = {1.9375, 0.046875, 0.0625};
        EXPECT_EQ(a.sum_unnormalized(w, 3), 2.0);
    }
    {
        // a large first operand sets the quantum for the whole chain:
        // 16 - 16 + 0.75 - 0.25 at E = 4 (quantum 1): 0 + 0.75 -> 1, 1 - 0.25 -> 1
        const double t[4] = {16.0, -16.0, 0.75, -0.25};
        EXPECT_EQ(a.sum_unnormalized(t, 4), 1.0);
        EXPECT_EQ(z.sum_unnormalized(t, 4), 0.0);  // 0.75 -> 0; 0 - 0.25 -> -0
        EXPECT_EQ(norm.add(norm.add(norm.add(16.0, -16.0), 0.75), -0.25), 0.5);
    }
}

TEST(NumFormat, UnnormalizedPlaneSphereTestOnHandComputedCases) {
    // Eq. 1 with products 1.0625, -1, 3/256 and w = 0: the normalised PSI
    // finds |d| = 0.07421875, the unnormalised one 0.0625. A sphere of radius
    // 0.0703125 (= 18/256) lies between: only the unnormalised PSI reports it.
    const raplas::Plane pl{{1.0f, 1.0f, 1.0f}, 0.0f};
    const raplas::Sphere sp{{1.0625f, -1.0f, 0.01171875f}, 0.0703125f};
    ArithSoft un{NumFormat::parse("fp1-8-4-psiunnorm"), true};
    ArithSoft no{NumFormat::parse("fp1-8-4"), true};
    EXPECT_TRUE(raplas::plane_hits_sphere(un, raplas::load(un, pl), raplas::load(un, sp)));
    EXPECT_FALSE(raplas::plane_hits_sphere(no, raplas::load(no, pl), raplas::load(no, sp)));
    // the batched path used by the tracer and the models gives the same answers
    for (const ArithSoft* a : {&un, &no}) {
        raplas::SphereSoA<ArithSoft> soa;
        soa.push_back(raplas::load(*a, sp));
        const raplas::PlaneA<ArithSoft> p = raplas::load(*a, pl);
        std::uint32_t mask = 0;
        raplas::plane_masks(*a, &p, 1, soa, 0, 1, &mask);
        EXPECT_EQ(mask != 0, raplas::plane_hits_sphere(*a, p, raplas::load(*a, sp)));
    }
    // w joins at the same coarse quantum: products 4, -4, 0.1875 and w = -0.0625;
    // 4 - 4 = 0 at E = 2 (quantum 1/4): + 0.1875 -> 0.75 quanta -> 0.25; - 0.0625 -> 0.1875
    // -> 0.75 quanta -> 0.25. Normalised: 0.125.
    const raplas::Plane p2{{1.0f, 1.0f, 1.0f}, -0.0625f};
    const raplas::Sphere s2{{4.0f, -4.0f, 0.1875f}, 0.1875f};
    EXPECT_FALSE(raplas::plane_hits_sphere(un, raplas::load(un, p2), raplas::load(un, s2)));  // 0.25 > 0.1875
    EXPECT_TRUE(raplas::plane_hits_sphere(no, raplas::load(no, p2), raplas::load(no, s2)));   // 0.125 <= 0.1875
}

TEST(NumFormat, BitLevelRoundingEqualsTheReference) {
    // round() rounds normal results in the double's bit pattern; it must equal
    // the scaling reference everywhere, including carries into the exponent,
    // steps below a power of two, the edges of the range and subnormals.
    FloatGen g(4242);
    int checked = 0;
    for (const char* name : {"fp1-7-16", "fp1-7-16-rtz", "fp1-8-15", "fp1-6-17-rtz", "fp1-5-10", "fp1-4-3-ftz",
                             "fp1-8-2", "fp1-8-23-rtz", "fp1-11-25", "fp1-3-1-rtz"}) {
        const NumFormat f = NumFormat::parse(name);
        for (int i = 0; i < 20000; ++i) {
            double x = g.next();
            const std::uint64_t r = g.bits();
            if (r % 4 == 0) x = std::ldexp(x, int(r >> 8) % 64 - 32);                    // out of float's way
            if (r % 7 == 0) x = std::nextafter(std::ldexp(1.0, int(r >> 20) % 40 - 20), 0.0);  // just below 2^k
            const int res = int(r >> 40) % 3 - 1;
            const double a = f.round(x, res), b = f.round_reference(x, res);
            ASSERT_TRUE(a == b && std::signbit(a) == std::signbit(b))
                << name << " x=" << x << " residual " << res << ": " << a << " vs " << b;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 200000);
}

TEST(NumFormat, UnnormalizedSumEqualsAFixedPointReference) {
    // An independent model of the adder without normalisation in 64-bit
    // fixed point (every value here is a multiple of 2^-40 below 2^22): align,
    // add exactly, carry, round at the stored exponent.
    constexpr int kFix = 40;
    for (const char* name : {"fp1-8-10", "fp1-8-10-rtz", "fp1-7-4", "fp1-7-4-rtz"}) {
        const NumFormat f = NumFormat::parse(name);
        const ArithSoft a{f, true};
        const int M = f.man_bits;
        std::uint64_t state = 777;
        auto rnd = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return state >> 11;
        };
        auto value = [&](int e) {  // random value of the format with exponent e
            const std::uint64_t r = rnd();
            const double m = 1.0 + double(r % (1u << M)) / double(1u << M);
            return std::ldexp((r >> 30) & 1 ? -m : m, e);
        };
        auto expo = [](double v) {  // stored exponent; 0 carries none (t[0] is never 0)
            int e;
            std::frexp(v, &e);
            return v == 0 ? -1000 : e - 1;
        };
        auto fix = [&](double v) { return static_cast<std::int64_t>(std::ldexp(v, kFix)); };
        int differs_from_normalised = 0;
        for (int it = 0; it < 20000; ++it) {
            double t[4];
            for (double& v : t) v = value(int(rnd() % 25) - 12);
            if (rnd() % 2) t[1] = f.round(-t[0] + value(int(rnd() % 10) - 16));  // cancellation
            if (rnd() % 7 == 0) t[1] = -t[0];                                 // exact 0 with an exponent
            std::int64_t S = fix(t[0]);
            int E = expo(t[0]);
            for (int i = 1; i < 4; ++i) {
                E = std::max(E, expo(t[i]));
                std::int64_t X = S + fix(t[i]);
                if (std::llabs(X) >= (std::int64_t(1) << (E + 1 + kFix))) ++E;
                const std::int64_t q = std::int64_t(1) << (E - M + kFix);
                std::int64_t k = X / q, rem = X % q;  // truncated toward zero
                if (f.rounding == raplas::Rounding::nearest_even) {
                    const std::int64_t twice = 2 * std::llabs(rem);
                    if (twice > q || (twice == q && (k & 1))) k += X < 0 ? -1 : 1;
                }
                S = k * q;
                if (std::llabs(S) >= (std::int64_t(1) << (E + 1 + kFix))) ++E;
            }
            const double want = std::ldexp(double(S), -kFix);
            const double got = a.sum_unnormalized(t, 4);
            ASSERT_EQ(got, want) << name << ": " << t[0] << " + " << t[1] << " + " << t[2] << " + " << t[3];
            differs_from_normalised += got != a.add(a.add(a.add(t[0], t[1]), t[2]), t[3]);
        }
        EXPECT_GT(differs_from_normalised, 200) << name;  // the cases exercise the difference
    }
}
