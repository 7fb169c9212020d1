// Small fixed-size vector used by every layer. No dependencies.
#pragma once

#include <cmath>
#include <cstddef>

namespace raplas {

template <class T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <class U>
    constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

    constexpr T operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }
    T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(T s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
    constexpr bool operator!=(const Vec3& o) const { return !(*this == o); }
};

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

template <class T> constexpr Vec3<T> operator*(T s, const Vec3<T>& v) { return v * s; }
template <class T> constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> inline T length(const Vec3<T>& v) { return std::sqrt(dot(v, v)); }
template <class T> inline Vec3<T> normalize(const Vec3<T>& v) {
    T l = length(v);
    return l > T(0) ? v / l : v;
}
template <class T> inline Vec3<T> vmin(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <class T> inline Vec3<T> vmax(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <class T> inline T max_abs(const Vec3<T>& v) {
    T a = std::fabs(v.x), b = std::fabs(v.y), c = std::fabs(v.z);
    return a > b ? (a > c ? a : c) : (b > c ? b : c);
}
template <class T> inline bool all_finite(const Vec3<T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline Vec3d to_d(const Vec3f& v) { return Vec3d(v); }
inline Vec3f to_f(const Vec3d& v) { return Vec3f(v); }

struct Aabb {
    Vec3d lo{1e300, 1e300, 1e300};
    Vec3d hi{-1e300, -1e300, -1e300};
    void grow(const Vec3d& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    bool empty() const { return lo.x > hi.x; }
    Vec3d center() const { return (lo + hi) * 0.5; }
    Vec3d extent() const { return hi - lo; }
};

}  // namespace raplas
