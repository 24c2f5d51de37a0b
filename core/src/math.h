// Small vector math and floating-point helpers shared by the whole core.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace gw {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kPi = 3.14159265358979323846;

// A float as the int x86's conversion (cvttss2si) makes it, as Cycles' textures get
// it: truncated towards 0, or INT32_MIN where it is out of int range or NaN.
inline int32_t x86_int(float f) { return std::abs(f) < 2147483648.0f ? int32_t(f) : INT32_MIN; }

template <class T>
struct V3 {
    T x = 0, y = 0, z = 0;
    V3() = default;
    V3(T a, T b, T c) : x(a), y(b), z(c) {}
    template <class U>
    explicit V3(const V3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
    // Components are contiguous (standard layout, checked below), so a runtime
    // axis index is a plain load; the watertight triangle test indexes by the
    // ray's permuted axes in its inner loop.
    T operator[](int i) const { return (&x)[i]; }
    T& operator[](int i) { return (&x)[i]; }
    V3 operator+(const V3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    V3 operator-(const V3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    V3 operator*(const V3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    V3 operator*(T s) const { return {x * s, y * s, z * s}; }
    V3 operator/(T s) const { return {x / s, y / s, z / s}; }
    V3 operator-() const { return {-x, -y, -z}; }
    V3& operator+=(const V3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    V3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
};
using Vec3 = V3<float>;
using Vec3d = V3<double>;
static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Vec3d) == 3 * sizeof(double), "V3 must be packed");

template <class T> inline T dot(const V3<T>& a, const V3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> inline V3<T> cross(const V3<T>& a, const V3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> inline T length(const V3<T>& a) { return std::sqrt(dot(a, a)); }
template <class T> inline V3<T> normalize(const V3<T>& a) {
    T l = length(a);
    return l > 0 ? a / l : a;
}
// Float vectors are first scaled by a power of two (exact) that brings their
// largest component to [1, 2): their squared length then neither overflows
// (from about 1.8e19 it did: a light 1e20 away had direction 0) nor loses its
// digits to underflow (below about 1e-19). Scaling by 2^k commutes exactly
// with the products, sums, square root and quotients below, so wherever the
// plain formula neither overflows nor underflows the result is bit-identical
// to it.
inline V3<float> scaled_to_unit(const V3<float>& a, int& exponent) {
    const float m = std::max(std::abs(a.x), std::max(std::abs(a.y), std::abs(a.z)));
    exponent = 0;
    // Squares of components up to 2^40 cannot overflow, and those of
    // components under 2^-63 are below the rounding of m^2 >= 2^-80: there the
    // plain formula is the scaled one's result, without libm calls (per hit).
    if (m >= 0x1p-40f && m <= 0x1p40f) return a;
    if (!(m > 0) || !std::isfinite(m)) return a;
    exponent = std::ilogb(m);
    return {std::ldexp(a.x, -exponent), std::ldexp(a.y, -exponent), std::ldexp(a.z, -exponent)};
}
inline float length(const V3<float>& a) {
    int e;
    const V3<float> s = scaled_to_unit(a, e);
    const float l = std::sqrt(dot(s, s));
    return e ? std::ldexp(l, e) : l;
}
inline V3<float> normalize(const V3<float>& a) {
    int e;
    const V3<float> s = scaled_to_unit(a, e);
    const float l = std::sqrt(dot(s, s));
    return l > 0 ? s / l : a;
}
template <class T> inline V3<T> vmin(const V3<T>& a, const V3<T>& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <class T> inline V3<T> vmax(const V3<T>& a, const V3<T>& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <class T> inline V3<T> vabs(const V3<T>& a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }
inline bool finite3(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline int max_axis(const Vec3& a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }

// Orthonormal basis around a unit vector n (Duff et al. 2017 construction).
inline void basis(const Vec3& n, Vec3& t, Vec3& b) {
    float s = std::copysign(1.0f, n.z);
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    t = {1.0f + s * n.x * n.x * a, s * c, -s * n.x};
    b = {c, s + n.y * n.y * a, -n.y};
}

// Rounding-error bound factor gamma(n) = n*eps / (1 - n*eps), eps = 2^-24 (Higham; pbrt 3.9).
constexpr float gamma_bound(int n) {
    return float(n) * (std::numeric_limits<float>::epsilon() * 0.5f) /
           (1.0f - float(n) * (std::numeric_limits<float>::epsilon() * 0.5f));
}

inline uint32_t float_bits(float f) { uint32_t u; std::memcpy(&u, &f, 4); return u; }
inline float bits_float(uint32_t u) { float f; std::memcpy(&f, &u, 4); return f; }
// Next representable float towards +inf / -inf (+0 and -0 both step to the smallest subnormal).
__attribute__((always_inline)) inline float next_up(float v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t u = float_bits(v);
    u = v >= 0 ? u + 1 : u - 1;
    return bits_float(u);
}
__attribute__((always_inline)) inline float next_down(float v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t u = float_bits(v);
    u = v > 0 ? u - 1 : u + 1;
    return bits_float(u);
}

}  // namespace gw
