#include "raplas/core/numfmt.hpp"

#include <cstdio>
#include <limits>
#include <stdexcept>

namespace raplas {

NumFormat NumFormat::parse(const std::string& text) {
    if (text == "float64" || text == "f64" || text == "double") return float64();
    if (text == "float32" || text == "f32" || text == "float") return float32();
    NumFormat f;
    f.kind = Kind::custom;
    int s = 0, e = 0, m = 0, used = 0;
    if (std::sscanf(text.c_str(), "fp%d-%d-%d%n", &s, &e, &m, &used) != 3 || s != 1)
        throw std::invalid_argument("number format '" + text +
                                    "' is not float64, float32 or fp1-<exp>-<man>[-rne|-rtz][-ftz]");
    std::string rest = text.substr(static_cast<std::size_t>(used));
    while (!rest.empty()) {
        if (rest.rfind("-rne", 0) == 0) { f.rounding = Rounding::nearest_even; rest = rest.substr(4); }
        else if (rest.rfind("-rtz", 0) == 0) { f.rounding = Rounding::toward_zero; rest = rest.substr(4); }
        else if (rest.rfind("-ftz", 0) == 0) { f.flush_subnormals = true; rest = rest.substr(4); }
        else throw std::invalid_argument("number format '" + text + "': unknown suffix '" + rest + "'");
    }
    if (e < 2 || e > 11) throw std::invalid_argument("number format '" + text + "': exponent bits must be 2..11");
    if (m < 1 || m > 25) throw std::invalid_argument("number format '" + text + "': fraction bits must be 1..25");
    f.exp_bits = e;
    f.man_bits = m;
    if (e == 8 && m == 23 && f.rounding == Rounding::nearest_even && !f.flush_subnormals) return float32();
    return f;
}

std::string NumFormat::name() const {
    if (kind == Kind::f64) return "float64";
    if (kind == Kind::f32) return "float32";
    std::string n = "fp1-" + std::to_string(exp_bits) + "-" + std::to_string(man_bits);
    if (rounding == Rounding::toward_zero) n += "-rtz";
    if (flush_subnormals) n += "-ftz";
    return n;
}

double NumFormat::max_finite() const {
    int bias = (1 << (exp_bits - 1)) - 1;
    return std::ldexp(2.0 - std::ldexp(1.0, -man_bits), bias);
}

double NumFormat::round(double x, int residual_sign) const {
    if (kind == Kind::f64) return x;
    if (kind == Kind::f32 && residual_sign == 0) return static_cast<double>(static_cast<float>(x));
    if (x == 0.0 || !std::isfinite(x)) return x;
    const int bias = (1 << (exp_bits - 1)) - 1;
    const int emin = 1 - bias;  // exponent of the smallest normal, as 2^emin
    int e2 = 0;
    std::frexp(x, &e2);  // |x| in [2^(e2-1), 2^e2)
    int q = (e2 - 1 > emin ? e2 - 1 : emin) - man_bits;  // quantum exponent
    double scaled = std::ldexp(x, -q);                 // exact
    double ip = std::trunc(scaled);
    double frac = std::fabs(scaled - ip);
    double r = ip;
    const bool neg = x < 0;
    // residual in the direction of |x|: +1 means the exact |value| is larger
    const int rmag = neg ? -residual_sign : residual_sign;
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

double ArithSoft::add_unnormalized(double a, double b, double s, int sign) const {
    // Without post-normalisation the sum keeps the quantum of the larger
    // operand: bits lost to cancellation are not recovered.
    if (a == 0.0 || b == 0.0) return f.round(s, sign);
    int ea = 0, eb = 0, es = 0;
    std::frexp(a, &ea);
    std::frexp(b, &eb);
    std::frexp(s, &es);
    int e = ea > eb ? ea : eb;
    if (es > e) e = es;
    int q = e - 1 - f.man_bits;
    double scaled = std::ldexp(s, -q);
    double ip = std::trunc(scaled);
    double frac = std::fabs(scaled - ip);
    if (f.rounding == Rounding::nearest_even && frac != 0.0) {
        bool up = frac > 0.5 || (frac == 0.5 && (sign != 0 ? ((s < 0) == (sign < 0)) : std::fmod(ip, 2.0) != 0.0));
        if (up) ip += (s < 0 ? -1.0 : 1.0);
    } else if (f.rounding == Rounding::toward_zero && frac == 0.0 && sign != 0 && ((s < 0) != (sign < 0))) {
        ip -= (s < 0 ? -1.0 : 1.0);
    }
    return f.round(std::ldexp(ip, q));
}

}  // namespace raplas
