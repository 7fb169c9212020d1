#include "raplas/core/numfmt.hpp"

#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace raplas {

namespace {

// NumFormat::parse without the -wt suffix (`full` is the text as given, for messages).
NumFormat parse_arith(const std::string& text, const std::string& full) {
    if (text == "float64" || text == "f64" || text == "double") return NumFormat::float64();
    if (text == "float32" || text == "f32" || text == "float") return NumFormat::float32();
    NumFormat f;
    f.kind = NumFormat::Kind::custom;
    int s = 0, e = 0, m = 0, used = 0;
    if (std::sscanf(text.c_str(), "fp%d-%d-%d%n", &s, &e, &m, &used) != 3 || s != 1)
        throw std::invalid_argument("number format '" + full +
                                    "' is not float64, float32 or fp1-<exp>-<man>[-rne|-rtz][-ftz][-psiunnorm], "
                                    "optionally followed by -wt");
    std::string rest = text.substr(static_cast<std::size_t>(used));
    while (!rest.empty()) {
        if (rest.rfind("-rne", 0) == 0) { f.rounding = Rounding::nearest_even; rest = rest.substr(4); }
        else if (rest.rfind("-rtz", 0) == 0) { f.rounding = Rounding::toward_zero; rest = rest.substr(4); }
        else if (rest.rfind("-ftz", 0) == 0) { f.flush_subnormals = true; rest = rest.substr(4); }
        else if (rest.rfind("-psiunnorm", 0) == 0) { f.psi_normalize = false; rest = rest.substr(10); }
        else throw std::invalid_argument("number format '" + full + "': unknown suffix '" + rest + "'");
    }
    if (e < 2 || e > 11) throw std::invalid_argument("number format '" + full + "': exponent bits must be 2..11");
    if (m < 1 || m > 25) throw std::invalid_argument("number format '" + full + "': fraction bits must be 1..25");
    f.exp_bits = e;
    f.man_bits = m;
    if (e == 8 && m == 23 && f.rounding == Rounding::nearest_even && !f.flush_subnormals && f.psi_normalize)
        return NumFormat::float32();
    return f;
}

}  // namespace

NumFormat NumFormat::parse(const std::string& full) {
    std::string text = full;
    RtiTest rti = RtiTest::division_free;
    if (text.size() > 3 && text.compare(text.size() - 3, 3, "-wt") == 0) {
        rti = RtiTest::watertight;
        text.resize(text.size() - 3);
    }
    NumFormat out = parse_arith(text, full);
    out.rti = rti;
    return out;
}

std::string NumFormat::name() const {
    const std::string wt = rti == RtiTest::watertight ? "-wt" : "";
    if (kind == Kind::f64) return "float64" + wt;
    if (kind == Kind::f32) return "float32" + wt;
    std::string n = "fp1-" + std::to_string(exp_bits) + "-" + std::to_string(man_bits);
    if (rounding == Rounding::toward_zero) n += "-rtz";
    if (flush_subnormals) n += "-ftz";
    if (!psi_normalize) n += "-psiunnorm";
    return n + wt;
}

void NumFormat::set_psi_normalize(bool on) {
    if (on == psi_normalize) return;
    if (!on && kind == Kind::f64)
        throw std::invalid_argument("a PSI without normalisation needs an emulated format (fp1-E-M, M <= 25), not float64");
    psi_normalize = on;
    if (!on && kind == Kind::f32) kind = Kind::custom;  // fp1-8-23, emulated
    if (on && kind == Kind::custom && exp_bits == 8 && man_bits == 23 && rounding == Rounding::nearest_even &&
        !flush_subnormals)
        kind = Kind::f32;
}

double NumFormat::max_finite() const {
    int bias = (1 << (exp_bits - 1)) - 1;
    return std::ldexp(2.0 - std::ldexp(1.0, -man_bits), bias);
}

double NumFormat::round_reference(double x, int residual_sign) const {
    if (kind == Kind::f64) return x;
    if (x == 0.0 || !std::isfinite(x)) return x;
    const int bias = (1 << (exp_bits - 1)) - 1;
    const int emin = 1 - bias;  // exponent of the smallest normal, as 2^emin
    const bool neg = x < 0;
    // residual in the direction of |x|: +1 means the exact |value| is larger
    const int rmag = neg ? -residual_sign : residual_sign;
    int e2 = 0;
    const double m = std::frexp(x, &e2);  // |x| in [2^(e2-1), 2^e2)
    // |x| a power of two with the exact value just below it: the exact value
    // lies in the binade below, whose quantum is half as large.
    if (std::fabs(m) == 0.5 && rmag < 0) --e2;
    int q = (e2 - 1 > emin ? e2 - 1 : emin) - man_bits;  // quantum exponent
    double scaled = std::ldexp(x, -q);                 // exact
    double ip = std::trunc(scaled);
    double frac = std::fabs(scaled - ip);
    double r = ip;
    if (rounding == Rounding::nearest_even) {
        bool up = false;
        if (frac > 0.5) up = true;
        else if (frac == 0.5) up = rmag != 0 ? rmag > 0 : std::fmod(ip, 2.0) != 0.0;  // tie: residual, else even
        if (up) r = ip + (neg ? -1.0 : 1.0);
    } else {
        // toward zero: exact value just below a representable |x| steps down
        if (frac == 0.0 && rmag < 0) r = ip - (neg ? -1.0 : 1.0);
    }
    double out = std::ldexp(r, q);
    if (std::fabs(out) > max_finite()) {
        if (rounding == Rounding::toward_zero) return neg ? -max_finite() : max_finite();
        return neg ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    }
    if (flush_subnormals && out != 0.0 && std::fabs(out) < min_normal()) return neg ? -0.0 : 0.0;
    return out;
}

namespace {

// 2^k for -1022 <= k <= 1023, from its bit pattern.
inline double pow2(int k) {
    const std::uint64_t b = std::uint64_t(k + 1023) << 52;
    double d;
    std::memcpy(&d, &b, sizeof d);
    return d;
}

}  // namespace

double ArithSoft::sum_unnormalized(const double* x, int n) const {
    const int bias = (1 << (f.exp_bits - 1)) - 1;
    const int emin = 1 - bias;
    // With at most 10 exponent bits every power of two below is a normal double.
    const bool small_range = f.exp_bits <= 10;
    auto p2 = [&](int k) { return small_range ? pow2(k) : std::ldexp(1.0, k); };
    constexpr int kZero = std::numeric_limits<int>::min() / 4;  // stored exponent of an unset 0
    auto expo = [&](double v) {
        if (v == 0.0) return kZero;
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        int e = int((bits >> 52) & 0x7ff) - 1023;
        if (e == -1023) {  // a subnormal double (formats with 11 exponent bits)
            std::frexp(v, &e);
            --e;
        }
        return e > emin ? e : emin;
    };
    double s = x[0];
    int es = expo(s);
    for (int i = 1; i < n; ++i) {
        const double b = x[i];
        const int eb = expo(b);
        int e = es > eb ? es : eb;
        if (e == kZero) {  // 0 + 0
            s = s + b;
            continue;
        }
        const double sd = s + b;
        if (!std::isfinite(sd)) return sd;  // an infinite operand (overflowed product): inf or NaN
        const double bb = sd - s;
        const double err = (s - (sd - bb)) + (b - bb);  // s + b == sd + err exactly
        const bool neg = sd < 0;
        // residual in the direction of |exact sum|: +1 larger, -1 smaller
        const int rmag = err == 0 ? 0 : ((err > 0) != neg ? 1 : -1);
        const double carry_at = p2(e + 1);
        if (std::fabs(sd) > carry_at || (std::fabs(sd) == carry_at && rmag >= 0)) ++e;
        const int q = e - f.man_bits;
        const double scaled = small_range ? sd * pow2(-q) : std::ldexp(sd, -q);  // exact; |scaled| <= 2^(M+1)
        const std::int64_t ii = static_cast<std::int64_t>(scaled);                // toward zero
        double ip = static_cast<double>(ii);
        const double frac = std::fabs(scaled - ip);
        if (f.rounding == Rounding::nearest_even) {
            bool up = false;
            if (frac > 0.5) up = true;
            else if (frac == 0.5) up = rmag != 0 ? rmag > 0 : (ii & 1) != 0;
            if (up) ip += neg ? -1.0 : 1.0;
        } else if (frac == 0.0 && rmag < 0) {
            ip -= neg ? -1.0 : 1.0;
        }
        if (ip == 0.0) ip = neg ? -0.0 : 0.0;
        double r = small_range ? ip * pow2(q) : std::ldexp(ip, q);
        if (std::fabs(r) > f.max_finite()) {
            r = f.rounding == Rounding::toward_zero ? (neg ? -f.max_finite() : f.max_finite())
                                                     : (neg ? -std::numeric_limits<double>::infinity()
                                                            : std::numeric_limits<double>::infinity());
            return r;
        }
        if (std::fabs(r) >= p2(e + 1)) ++e;  // rounded up into the next binade
        if (f.flush_subnormals && e == emin && r != 0.0 && std::fabs(r) < f.min_normal()) r = neg ? -0.0 : 0.0;
        s = r;
        es = e;  // kept even when r has leading zeros (or is 0)
    }
    return s;
}

double ArithSoft::add_unnormalized(double a, double b) const {
    const double ab[2] = {a, b};
    return sum_unnormalized(ab, 2);
}

}  // namespace raplas
