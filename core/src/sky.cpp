// The clear sky's light (sky.h). Constants are those of Cycles' intern/sky, so
// that a table computed here matches the one Blender renders with.
#include "sky.h"

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "threads.h"

namespace gw {
namespace {

constexpr float kPi = 3.14159265358979f;

struct F3 {
    float x, y, z;
};
F3 operator+(F3 a, F3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
F3 operator*(float s, F3 a) { return {s * a.x, s * a.y, s * a.z}; }
float dot(F3 a, F3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
float length(F3 a) { return std::sqrt(dot(a, a)); }

// Runs body(i) for i in [0, n) on up to `threads` threads.
template <class Body>
void parallel_for(size_t n, int threads, const Body& body) {
    const size_t workers = std::min<size_t>(size_t(resolve_threads(threads)), std::max<size_t>(1, n / 256));
    if (workers <= 1) {
        for (size_t i = 0; i < n; ++i) body(i);
        return;
    }
    std::vector<std::thread> pool;
    for (size_t w = 0; w < workers; ++w)
        pool.emplace_back([&, w] {
            for (size_t i = w * n / workers, end = (w + 1) * n / workers; i < end; ++i) body(i);
        });
    for (auto& t : pool) t.join();
}

// ---- Single scattering (Nishita), metres --------------------------------------------------

constexpr float kEarth = 6360e3f, kTop = 6420e3f;
constexpr float kRayleighScale = 8e3f, kMieScale = 1.2e3f, kMieCoeff = 2e-5f, kMieG = 0.76f;
constexpr float kMieExtinction = 1.11f;   // Mie extinction over Mie scattering
constexpr int kSteps = 32, kWavelengths = 21;
constexpr float kStepLambda = 20.0f;     // 380..780 nm

// Per wavelength: the sun's irradiance above the atmosphere (W m^-2 nm^-1),
// Rayleigh scattering and ozone absorption at unit density (m^-1), and the CIE
// 1931 colour-matching functions.
constexpr float kIrradiance[kWavelengths] = {
    1.45756830f, 1.56596306f, 1.65148449f, 1.71496243f, 1.75797984f, 1.78256408f, 1.79095108f,
    1.78541550f, 1.76815555f, 1.74122070f, 1.70647127f, 1.66556087f, 1.61993437f, 1.57083597f,
    1.51932335f, 1.46628495f, 1.41245853f, 1.35844962f, 1.30474914f, 1.25174963f, 1.19975999f};
constexpr float kRayleigh[kWavelengths] = {
    5.424820088e-05f, 4.418549867e-05f, 3.635151910e-05f, 3.017929012e-05f, 2.526320227e-05f,
    2.130859311e-05f, 1.809838025e-05f, 1.547057129e-05f, 1.330284977e-05f, 1.150184784e-05f,
    9.995574300e-06f, 8.727999736e-06f, 7.655137010e-06f, 6.742172038e-06f, 5.961341258e-06f,
    5.290345981e-06f, 4.711156876e-06f, 4.209104811e-06f, 3.772183813e-06f, 3.390512555e-06f,
    3.055915317e-06f};
constexpr float kOzone[kWavelengths] = {
    3.251268499e-09f, 5.853953650e-09f, 1.977191155e-08f, 7.309568763e-08f, 2.008456151e-07f,
    4.038395810e-07f, 6.355133591e-07f, 9.670704118e-07f, 1.547974004e-06f, 2.090386472e-06f,
    2.461280562e-06f, 2.735512995e-06f, 2.151258631e-06f, 1.590518408e-06f, 1.123561980e-06f,
    7.352755149e-07f, 4.645013036e-07f, 3.309607992e-07f, 2.251261229e-07f, 1.487912927e-07f,
    1.682862336e-07f};
constexpr float kCmf[kWavelengths][3] = {
    {0.00136800000f, 0.00003900000f, 0.00645000100f}, {0.01431000000f, 0.00039600000f, 0.06785001000f},
    {0.13438000000f, 0.00400000000f, 0.64560000000f}, {0.34828000000f, 0.02300000000f, 1.74706000000f},
    {0.29080000000f, 0.06000000000f, 1.66920000000f}, {0.09564000000f, 0.13902000000f, 0.81295010000f},
    {0.00490000000f, 0.32300000000f, 0.27200000000f}, {0.06327000000f, 0.71000000000f, 0.07824999000f},
    {0.29040000000f, 0.95400000000f, 0.02030000000f}, {0.59450000000f, 0.99500000000f, 0.00390000000f},
    {0.91630000000f, 0.87000000000f, 0.00165000100f}, {1.06220000000f, 0.63100000000f, 0.00080000000f},
    {0.85444990000f, 0.38100000000f, 0.00019000000f}, {0.44790000000f, 0.17500000000f, 0.00002000000f},
    {0.16490000000f, 0.06100000000f, 0.00000000000f}, {0.04677000000f, 0.01700000000f, 0.00000000000f},
    {0.01135916000f, 0.00410200000f, 0.00000000000f}, {0.00289932700f, 0.00104700000f, 0.00000000000f},
    {0.00069007860f, 0.00024920000f, 0.00000000000f}, {0.00016615050f, 0.00006000000f, 0.00000000000f},
    {0.00004150994f, 0.00001499000f, 0.00000000000f}};

// 8-point Gauss-Laguerre over the path to the top of the atmosphere: nodes as
// fractions of the path, weights with exp(node) folded in.
constexpr float kNodes[8] = {0.006811185292f, 0.03614807107f, 0.09004346519f, 0.1706680068f,
                             0.2818362161f,   0.4303406404f,  0.6296271457f,  0.9145252695f};
constexpr float kWeights[8] = {0.01750893642f, 0.04135477391f, 0.06678839063f, 0.09507698807f,
                               0.1283416365f,  0.1707430204f,  0.2327233347f,  0.3562490486f};

F3 densities(float height) {
    float ozone = 0;
    if (height >= 10000.0f && height < 25000.0f) ozone = height / 15000.0f - 2.0f / 3.0f;
    else if (height >= 25000.0f && height < 40000.0f) ozone = 8.0f / 3.0f - height / 15000.0f;
    return {std::exp(-height / kRayleighScale), std::exp(-height / kMieScale), ozone};
}

// Distance from p (inside the sphere of radius r) along unit d to the sphere.
float to_sphere(F3 p, F3 d, float r) {
    const float b = dot(p, d), c = dot(p, p) - r * r;
    return -b + std::sqrt(std::max(b * b - c, 0.0f));
}

F3 optical_depth(F3 p, F3 d) {
    const float length_ = to_sphere(p, d, kTop);
    F3 depth{0, 0, 0};
    for (int i = 0; i < 8; ++i) {
        const F3 q = p + (kNodes[i] * length_) * d;
        depth = depth + kWeights[i] * densities(length(q) - kEarth);
    }
    return length_ * depth;
}

bool earth_blocks(F3 p, F3 d) {
    if (d.z >= 0) return false;
    const float b = dot(p, d);
    return b * b - (dot(p, p) - kEarth * kEarth) >= 0;
}

F3 spectrum_to_xyz(const float* s) {
    F3 xyz{0, 0, 0};
    for (int w = 0; w < kWavelengths; ++w) xyz = xyz + s[w] * F3{kCmf[w][0], kCmf[w][1], kCmf[w][2]};
    return kStepLambda * xyz;
}

F3 single_scattering(F3 view, F3 sun, const SkyAtmosphere& a) {
    const F3 origin{0, 0, kEarth + a.altitude}, scale{a.air, a.dust, a.ozone};
    const float segment = to_sphere(origin, view, kTop) / kSteps;
    const float mu = dot(view, sun), g2 = kMieG * kMieG;
    const float rayleigh_phase = 3.0f / (16.0f * kPi) * (1.0f + mu * mu);
    const float mie_phase = 3.0f * (1.0f - g2) * (1.0f + mu * mu) /
                            (8.0f * kPi * (2.0f + g2) * std::pow(1.0f + g2 - 2.0f * kMieG * mu, 1.5f));
    float spectrum[kWavelengths] = {};
    F3 depth{0, 0, 0};
    for (int i = 0; i < kSteps; ++i) {
        const F3 p = origin + ((i + 0.5f) * segment) * view;
        const F3 d0 = densities(length(p) - kEarth);
        const F3 density{d0.x * scale.x, d0.y * scale.y, d0.z * scale.z};
        depth = depth + segment * density;
        if (earth_blocks(p, sun)) continue;
        const F3 l0 = optical_depth(p, sun);
        const F3 total{depth.x + l0.x * scale.x, depth.y + l0.y * scale.y, depth.z + l0.z * scale.z};
        for (int w = 0; w < kWavelengths; ++w) {
            const float attenuation =
                std::exp(-(total.x * kRayleigh[w] + total.y * kMieExtinction * kMieCoeff + total.z * kOzone[w]));
            const float scattering = density.x * kRayleigh[w] * rayleigh_phase + density.y * kMieCoeff * mie_phase;
            spectrum[w] += attenuation * scattering * kIrradiance[w] * segment;
        }
    }
    return spectrum_to_xyz(spectrum);
}

// ---- Multiple scattering (Blender 5.0), kilometres ----------------------------------------

constexpr float kR = 6371.0f, kRTop = 6471.0f, kAlbedo = 0.3f, kAerosolG = 0.8f;
constexpr int kMsSteps = 64, kTw = 256, kTh = 64;
constexpr int kBands = 4;   // 630, 560, 490, 430 nm
constexpr float kSun[kBands] = {1.679f, 1.828f, 1.986f, 1.307f};
constexpr float kMolecular[kBands] = {6.605e-3f, 1.067e-2f, 1.842e-2f, 3.156e-2f};
constexpr float kOzoneCross[kBands] = {3.472e-25f, 3.914e-25f, 1.349e-25f, 11.03e-27f};
constexpr float kAerosolAbsorb[kBands] = {2.8722e-24f, 4.6168e-24f, 7.9706e-24f, 1.3578e-23f};
constexpr float kAerosolScatter[kBands] = {1.5908e-22f, 1.7711e-22f, 2.0942e-22f, 2.4033e-22f};
constexpr float kMultiple[kBands] = {0.217f, 0.347f, 0.594f, 1.0f};
constexpr double kToXyz[kBands][3] = {{53.386917738564668023, 22.981337506691024754, 0.0},
                                      {43.904844466369358263, 71.347795700053393866, 0.102506867965741307},
                                      {1.6137278251608962005, 18.422960591455485011, 31.742921188390805758},
                                      {20.762668673810577145, 2.3614213523314368527, 110.48009643252140334}};
constexpr float kOzoneDobson = 334.5f, kAerosolBase = 1.3681e20f, kAerosolBackground = 2e6f, kAerosolScale = 0.73f;

struct Bands {
    float v[kBands];
};

struct Medium {
    Bands scatter_molecular, scatter_aerosol, extinction;
};

Medium medium(float h, const SkyAtmosphere& a) {
    const float hh = std::max(h, 1e-4f), lh = std::log(hh);
    const float ozone = 3.78547397e20f * std::exp(-(lh - 3.22261f) * (lh - 3.22261f) * 5.55555555f - lh);
    const float aerosol = kAerosolBase * (std::exp(-h / kAerosolScale) + kAerosolBackground / kAerosolBase) * a.dust;
    const float molecular = std::exp(-0.07771971f * std::pow(h, 1.16364243f)) * a.air;
    Medium m;
    for (int b = 0; b < kBands; ++b) {
        m.scatter_molecular.v[b] = kMolecular[b] * molecular;
        m.scatter_aerosol.v[b] = kAerosolScatter[b] * aerosol;
        m.extinction.v[b] = m.scatter_molecular.v[b] + m.scatter_aerosol.v[b] + kAerosolAbsorb[b] * aerosol +
                            kOzoneCross[b] * kOzoneDobson * ozone * a.ozone;
    }
    return m;
}

// Transmittance from altitude (fraction a of the 100 km atmosphere) towards a
// direction at cos(zenith angle) c, to the top of the atmosphere, ignoring the Earth.
Bands transmittance(float c, float a, const SkyAtmosphere& at) {
    const F3 origin{0, 0, kR + a * 100.0f}, d{-std::sqrt(std::max(0.0f, 1 - c * c)), 0, c};
    const float dt = to_sphere(origin, d, kRTop) / kMsSteps;
    Bands depth{};
    for (int i = 0; i < kMsSteps; ++i) {
        const F3 p = origin + ((i + 0.5f) * dt) * d;
        const Medium m = medium(std::max(length(p) - kR, 0.0f), at);
        for (int b = 0; b < kBands; ++b) depth.v[b] += m.extinction.v[b] * dt;
    }
    Bands t;
    for (int b = 0; b < kBands; ++b) t.v[b] = std::exp(-depth.v[b]);
    return t;
}

struct TransmittanceTable {
    std::vector<Bands> t = std::vector<Bands>(kTw * kTh);
    static float saturate(float x) { return x > 0 ? (x < 1 ? x : 1.0f) : 0.0f; }   // (NaN -> 0)
    Bands at(float c, float a) const {
        const float fx = (kTw - 1) * saturate(0.5f * c + 0.5f);
        const float fy = (kTh - 1) * saturate(a);
        const int x0 = std::min(int(fx), kTw - 2), y0 = std::min(int(fy), kTh - 2);
        const float sx = fx - x0, sy = fy - y0;
        Bands out;
        for (int b = 0; b < kBands; ++b) {
            const float lo = t[y0 * kTw + x0].v[b] * (1 - sx) + t[y0 * kTw + x0 + 1].v[b] * sx;
            const float hi = t[(y0 + 1) * kTw + x0].v[b] * (1 - sx) + t[(y0 + 1) * kTw + x0 + 1].v[b] * sx;
            out.v[b] = lo * (1 - sy) + hi * sy;
        }
        return out;
    }
};

// Light scattered more than once (a fit) plus the ground's bounce, per band.
Bands multiple_and_ground(const TransmittanceTable& table, float c, float a, float r) {
    const float omega = 2 * kPi * (1 - std::sqrt(std::max(0.0f, 1 - (kR / r) * (kR / r))));
    const Bands tg = table.at(c, 0), t1 = table.at(1, 0), ta = table.at(1, a);
    Bands out;
    for (int b = 0; b < kBands; ++b) {
        // (t1 / ta: the sun's light reaching the ground over what reaches this height; 0 where none does)
        const float ratio = ta.v[b] > 0 ? t1.v[b] / ta.v[b] : 0.0f;
        const float ground = omega / (4 * kPi) * (kAlbedo / kPi) * tg.v[b] * ratio * c;
        out.v[b] = 0.02f * kMultiple[b] / (1 + 5 * std::exp(-17.92f * c)) + ground;
    }
    return out;
}

// Distance along unit d from p to the sphere of radius r: the far crossing from
// inside, the near one from outside; -1 where the ray misses it.
float sphere_distance(F3 p, F3 d, float r) {
    const float b = dot(p, d), c = dot(p, p) - r * r, disc = b * b - c;
    if (disc < 0) return -1;
    const float s = std::sqrt(disc);
    if (c <= 0) return -b + s;
    const float t = -b - s;
    return t >= 0 ? t : -1;
}

F3 bands_to_xyz(const Bands& l) {
    double x = 0, y = 0, z = 0;
    for (int b = 0; b < kBands; ++b) {
        x += l.v[b] * kToXyz[b][0];
        y += l.v[b] * kToXyz[b][1];
        z += l.v[b] * kToXyz[b][2];
    }
    return {float(x), float(y), float(z)};
}

F3 multiple_scattering(const TransmittanceTable& table, F3 view, F3 sun, const SkyAtmosphere& a) {
    const F3 origin{0, 0, kR + a.altitude};
    const float ground = sphere_distance(origin, view, kR);
    const float distance = ground > 0 ? ground : sphere_distance(origin, view, kRTop);
    const float dt = std::max(distance, 0.0f) / kMsSteps;
    const float c = -dot(view, sun), g2 = kAerosolG * kAerosolG;
    const float phase_molecular = 3.0f / (16.0f * kPi) * (1 + c * c);
    const float phase_aerosol = 1.0f / (4 * kPi) * (1 - g2) / std::pow(1 + g2 + 2 * kAerosolG * c, 1.5f);
    Bands light{}, through{{1, 1, 1, 1}};
    for (int i = 0; i < kMsSteps; ++i) {
        const F3 p = origin + ((i + 0.5f) * dt) * view;
        const float r = length(p), h = std::max(r - kR, 0.0f), alt = h / 100.0f;
        const float cos_sun = dot((1 / r) * p, sun);
        const Medium m = medium(h, a);
        const Bands to_sun = table.at(cos_sun, alt), more = multiple_and_ground(table, cos_sun, alt, r);
        for (int b = 0; b < kBands; ++b) {
            const float s = kSun[b] * (m.scatter_molecular.v[b] * (phase_molecular * to_sun.v[b] + more.v[b]) +
                                       m.scatter_aerosol.v[b] * (phase_aerosol * to_sun.v[b] + more.v[b]));
            const float step = std::exp(-dt * m.extinction.v[b]);
            light.v[b] += through.v[b] * (s - s * step) / std::max(m.extinction.v[b], 1e-7f);
            through.v[b] *= step;
        }
    }
    return bands_to_xyz(light);
}

}  // namespace

void sky_sun(bool multiple, float elevation, float solid_angle, const SkyAtmosphere& a, float* xyz) {
    F3 v;
    if (multiple) {
        const Bands t = transmittance(std::sin(elevation), a.altitude / 100.0f, a);
        Bands l;
        for (int b = 0; b < kBands; ++b) l.v[b] = kSun[b] * t.v[b] / solid_angle;
        v = bands_to_xyz(l);
    } else {
        const F3 depth = optical_depth({0, 0, kEarth + a.altitude}, {std::cos(elevation), 0, std::sin(elevation)});
        float spectrum[kWavelengths];
        for (int w = 0; w < kWavelengths; ++w)
            spectrum[w] = kIrradiance[w] *
                          std::exp(-(kRayleigh[w] * depth.x * a.air + kMieExtinction * kMieCoeff * depth.y * a.dust)) /
                          solid_angle;
        v = spectrum_to_xyz(spectrum);
    }
    xyz[0] = v.x, xyz[1] = v.y, xyz[2] = v.z;
}

void sky_single_scattering(const float* views, size_t n, float sun_elevation, const SkyAtmosphere& a, float* xyz,
                           int threads) {
    const F3 sun{std::cos(sun_elevation), 0, std::sin(sun_elevation)};
    parallel_for(n, threads, [&](size_t i) {
        const F3 v = single_scattering({views[3 * i], views[3 * i + 1], views[3 * i + 2]}, sun, a);
        xyz[3 * i] = v.x, xyz[3 * i + 1] = v.y, xyz[3 * i + 2] = v.z;
    });
}

void sky_multiple_scattering(const float* views, size_t n, float sun_elevation, const SkyAtmosphere& a, float* xyz,
                             int threads) {
    TransmittanceTable table;
    parallel_for(size_t(kTh), threads, [&](size_t y) {
        for (int x = 0; x < kTw; ++x)
            table.t[y * kTw + x] = transmittance(2.0f * x / (kTw - 1) - 1, float(y) / (kTh - 1), a);
    });
    const float c = std::sin(sun_elevation);
    const F3 sun{-std::sqrt(std::max(0.0f, 1 - c * c)), 0, c};
    parallel_for(n, threads, [&](size_t i) {
        const F3 v = multiple_scattering(table, {views[3 * i], views[3 * i + 1], views[3 * i + 2]}, sun, a);
        xyz[3 * i] = v.x, xyz[3 * i + 1] = v.y, xyz[3 * i + 2] = v.z;
    });
}

}  // namespace gw
