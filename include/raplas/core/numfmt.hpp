// Number formats of the intersectors. The kernels in intersect.hpp are written
// against an "Arith" policy (add/sub/mul/div/cvt on a value type T), so the same
// source runs in float64, float32 or an emulated reduced-precision float.
// No dependencies beyond the standard library.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace raplas {

enum class Rounding : std::uint8_t { nearest_even, toward_zero };

// The Ray-Triangle Intersector's test: the paper's division-free Eq. 2, or the
// watertight test of Woop, Benthin and Wald (JCGT 2013; watertight.hpp).
enum class RtiTest : std::uint8_t { division_free, watertight };

// A binary floating-point format: 1 sign bit, `exp_bits` exponent bits (IEEE
// bias), `man_bits` stored fraction bits (hidden leading 1), gradual underflow
// unless `flush_subnormals`. float32 and float64 run natively; any other
// combination is emulated bit-exactly (see round()).
struct NumFormat {
    enum class Kind : std::uint8_t { f64, f32, custom };
    Kind kind = Kind::f32;
    int exp_bits = 8;
    int man_bits = 23;
    Rounding rounding = Rounding::nearest_even;
    bool flush_subnormals = false;
    // false: the Plane-Sphere Intersector's adders do not renormalise after
    // cancellation (paper §4; see ArithSoft::sum_unnormalized). Emulated
    // formats only; the Ray-Triangle Intersector always normalises.
    bool psi_normalize = true;
    // The ray-triangle test computed in this format (suffix -wt: watertight).
    RtiTest rti = RtiTest::division_free;

    static NumFormat float64() { return {Kind::f64, 11, 52, Rounding::nearest_even, false}; }
    static NumFormat float32() { return {Kind::f32, 8, 23, Rounding::nearest_even, false}; }
    // "float64", "float32", or "fp<S>-<E>-<M>[-rne|-rtz][-ftz][-psiunnorm]"
    // e.g. "fp1-7-16"; any of them with "-wt" at the end selects the watertight
    // ray-triangle test. Throws std::invalid_argument with a one-line reason.
    static NumFormat parse(const std::string& text);
    std::string name() const;
    // Switches the PSI normalisation; float32 becomes its emulated twin
    // fp1-8-23 when it is turned off. Throws std::invalid_argument for formats
    // that cannot be emulated (more than 25 fraction bits).
    void set_psi_normalize(bool on);
    int total_bits() const { return 1 + exp_bits + man_bits; }
    // Largest relative rounding error of one operation (unit roundoff).
    double unit_roundoff() const {
        return std::ldexp(1.0, -(man_bits + (rounding == Rounding::nearest_even ? 1 : 0)));
    }
    double max_finite() const;
    double min_normal() const { return std::ldexp(1.0, 2 - (1 << (exp_bits - 1))); }

    // Rounds x (taken as exact) into this format. `residual_sign` says on which
    // side of x the exact value lies when x is itself an already-rounded double
    // (+1 above, -1 below, 0 exact): it makes double-then-round bit-exact.
    double round(double x, int residual_sign = 0) const;
    // The same by scaling and truncation, for every case (round() takes a
    // bit-level shortcut for normal results and falls back to this).
    double round_reference(double x, int residual_sign = 0) const;
    bool operator==(const NumFormat& o) const {
        return kind == o.kind && exp_bits == o.exp_bits && man_bits == o.man_bits &&
               rounding == o.rounding && flush_subnormals == o.flush_subnormals && psi_normalize == o.psi_normalize &&
               rti == o.rti;
    }
};

inline double NumFormat::round(double x, int residual_sign) const {
    if (kind == Kind::f64) return x;
    if (kind == Kind::f32 && residual_sign == 0) return static_cast<double>(static_cast<float>(x));
    if (x == 0.0) return x;  // exact (and the residual of an exact zero sum is zero)
    // Normal inputs whose result is normal in the format: round the double's
    // fraction field to man_bits bits in place (a carry runs into the exponent).
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    const int e = int((b >> 52) & 0x7ff) - 1023;
    const int bias = (1 << (exp_bits - 1)) - 1;
    if (e >= 1 - bias && e <= bias && e != 1024 && e != -1023) {
        const std::uint64_t unit = std::uint64_t(1) << (52 - man_bits);
        const std::uint64_t low = b & (unit - 1);
        const int rmag = (b >> 63) ? -residual_sign : residual_sign;  // +1: exact |value| is larger
        std::uint64_t r = b - low;
        if (rounding == Rounding::nearest_even) {
            const std::uint64_t half = unit >> 1;
            if (low > half || (low == half && (rmag > 0 || (rmag == 0 && (r & unit) != 0)))) r += unit;
        } else if (low == 0 && rmag < 0) {
            r -= unit;  // just below: the largest value under x (borrows into the exponent at a power of two)
        }
        const int re = int((r >> 52) & 0x7ff) - 1023;
        if (re >= 1 - bias && re <= bias) {
            double out;
            std::memcpy(&out, &r, sizeof out);
            return out;
        }
    }
    return round_reference(x, residual_sign);
}

// ---- Arith policies -------------------------------------------------------

template <class F>
struct ArithNative {
    using T = F;
    RtiTest rti = RtiTest::division_free;
    T cvt(double x) const { return static_cast<T>(x); }
    T add(T a, T b) const { return a + b; }
    T sub(T a, T b) const { return a - b; }
    T mul(T a, T b) const { return a * b; }
    T div(T a, T b) const { return a / b; }
};
using ArithF32 = ArithNative<float>;
using ArithF64 = ArithNative<double>;

// Emulated format: values are carried in a double that always holds a value of
// the format; every operation is computed in double and rounded once, with the
// exact residual (TwoSum / FMA) deciding ties, so results equal a correctly
// rounded hardware operation for formats of up to 25 fraction bits.
struct ArithSoft {
    using T = double;
    NumFormat f;
    // When false, every add() is done by an adder without normalisation
    // (operands taken as normalised; see sum_unnormalized). The PSI uses
    // f.psi_normalize instead, through psi_sum() in intersect.hpp.
    bool normalize_add = true;

    T cvt(double x) const { return f.round(x); }
    T add(T a, T b) const {
        double s = a + b;
        double bb = s - a;
        double e = (a - (s - bb)) + (b - bb);  // TwoSum: a + b == s + e exactly
        int sign = e > 0 ? 1 : (e < 0 ? -1 : 0);
        if (!normalize_add) return add_unnormalized(a, b);
        return f.round(s, sign);
    }
    T sub(T a, T b) const { return add(a, -b); }
    T mul(T a, T b) const {
        double p = a * b;
        double e = std::fma(a, b, -p);
        return f.round(p, e > 0 ? 1 : (e < 0 ? -1 : 0));
    }
    T div(T a, T b) const {
        double q = a / b;
        double r = std::fma(-q, b, a);  // a - q*b exactly
        int sign = 0;
        if (r != 0 && std::isfinite(q)) sign = ((r > 0) == (b > 0)) ? 1 : -1;
        return f.round(q, sign);
    }


    // x[0] + x[1] + ... + x[n-1], left to right, by an adder without
    // normalisation. Each value carries a stored exponent E (a normalised
    // operand: floor(log2 |x|), at least the format's minimum exponent). An
    // addition aligns both operands to the larger E, adds exactly, shifts
    // right by one on a carry out (E+1), and rounds to M fraction bits at
    // that exponent, i.e. to a multiple of 2^(E-M); the result keeps E even
    // when cancellation leaves leading zeros, so bits lost there are not
    // recovered and later, smaller operands are rounded at the same coarse
    // quantum. Products entering the sum are normalised (a multiplier needs
    // at most a one-bit shift). Overflow as in round(); with flush_subnormals
    // a result below the smallest normal at the minimum exponent becomes 0.
    T sum_unnormalized(const T* x, int n) const;
    T add_unnormalized(T a, T b) const;  // sum_unnormalized of {a, b}
};

// The ray-triangle test an arithmetic policy computes.
template <class F> inline RtiTest rti_of(const ArithNative<F>& a) { return a.rti; }
inline RtiTest rti_of(const ArithSoft& a) { return a.f.rti; }

// Calls fn with the arithmetic policy of format f (ArithF32, ArithF64 or
// ArithSoft) and returns its result: one generic body for every format.
template <class Fn>
inline decltype(auto) with_arith(const NumFormat& f, Fn&& fn) {
    switch (f.kind) {
        case NumFormat::Kind::f64: return fn(ArithF64{f.rti});
        case NumFormat::Kind::custom: return fn(ArithSoft{f, true});
        case NumFormat::Kind::f32: break;
    }
    return fn(ArithF32{f.rti});
}

}  // namespace raplas
