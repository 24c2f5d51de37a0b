// Blender's Voronoi Texture. See voronoi.h.
#include "voronoi.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "lookup3.h"

namespace gw {
namespace {

constexpr int kMaxDims = 4;

struct Octave {
    float distance = 0;
    float color[3] = {0, 0, 0};
    float position[kMaxDims] = {0, 0, 0, 0};   // x, y, z, w as Cycles lays them (1D: w)
};

// The point's place in cell c, each coordinate in [0, 1] (Cycles' hash_floatN_to_floatN).
void lookup3_point(int n, const float* c, float* out) {
    out[0] = hash_floats(n, c);
    if (n == 2) out[1] = hash_floats_with(2, c, 1.0f);
    if (n == 3) {
        out[1] = hash_floats_with(3, c, 1.0f);
        out[2] = hash_floats_with(3, c, 2.0f);
    }
    if (n == 4) {
        for (int r = 1; r < 4; ++r) {   // the coordinates turned by r places: (w, x, y, z), (z, w, x, y), (y, z, w, x)
            float k[4];
            for (int i = 0; i < 4; ++i) k[i] = c[(i + 4 - r) % 4];
            out[r] = hash_floats(4, k);
        }
    }
}

float metric_distance(const Texture& t, int n, const float* a, const float* b) {
    if (n == 1) return std::abs(b[0] - a[0]);
    float sum = 0, most = 0;
    for (int i = 0; i < n; ++i) {
        const float d = std::abs(a[i] - b[i]);
        switch (t.voronoi_metric) {
        case VoronoiMetric::Euclidean: sum += d * d; break;
        case VoronoiMetric::Manhattan: sum += d; break;
        case VoronoiMetric::Chebychev: most = std::max(most, d); break;
        case VoronoiMetric::Minkowski: sum += std::pow(d, t.exponent); break;
        }
    }
    switch (t.voronoi_metric) {
    case VoronoiMetric::Euclidean: return std::sqrt(sum);
    case VoronoiMetric::Manhattan: return sum;
    case VoronoiMetric::Chebychev: return most;
    case VoronoiMetric::Minkowski: return std::pow(sum, 1.0f / t.exponent);
    }
    return 0;
}

inline float mix(float a, float b, float t) { return a + t * (b - a); }

// Cycles' smoothstep from 0 to 1.
inline float smooth01(float x) {
    if (x < 0) return 0;
    if (x >= 1) return 1;
    return (3.0f - 2.0f * x) * (x * x);
}

// Calls f(offset) for each cell offset in [-reach, reach]^n, x fastest, the last axis slowest.
template <class F>
void each_neighbour(int n, int reach, F&& f) {
    const int side = 2 * reach + 1;
    int total = 1;
    for (int i = 0; i < n; ++i) total *= side;
    for (int index = 0; index < total; ++index) {
        float offset[kMaxDims];
        for (int i = 0, rest = index; i < n; ++i, rest /= side) offset[i] = float(rest % side - reach);
        f(offset);
    }
}

// A cell: its corner, and its integer coordinates for the PCG hash.
struct Cell {
    float at[kMaxDims];
    int32_t index[kMaxDims];
};

// The point's place in its cell and the cell's colour, hashed as t says: Blender 5.0's
// PCG of the integer cell (t.voronoi_pcg; 1D keeps lookup3), before it lookup3 of the
// corner's float bits.
void point_of(const Texture& t, int n, const Cell& c, float* out) {
    if (t.voronoi_pcg && n > 1) hash_pcg(n, c.index, out);
    else lookup3_point(n, c.at, out);
}

void color_of(const Texture& t, int n, const Cell& c, float* out) {
    if (t.voronoi_pcg && n > 1) {
        float h[4];
        const int32_t flat[3] = {c.index[0], c.index[1], 0};   // (2D: the 3D hash at z = 0)
        hash_pcg(n == 2 ? 3 : n, n == 2 ? flat : c.index, h);
        std::copy(h, h + 3, out);
    } else {
        hash_floats_to_color(n, c.at, out);   // (the cell's colour)
    }
}

// The cell coord lies in and the points of the cells around it.
struct Around {
    const Texture& t;
    int n;
    float randomness;
    float cell[kMaxDims], local[kMaxDims];   // the cell's corner; coord relative to it
    int32_t index[kMaxDims];
    Around(const Texture& tex, int dims, const float* coord, float random) : t(tex), n(dims), randomness(random) {
        for (int i = 0; i < n; ++i) {
            cell[i] = std::floor(coord[i]);
            local[i] = coord[i] - cell[i];
            index[i] = x86_int(cell[i]);
        }
    }
    // The point of the cell at `offset` from this one, relative to this cell.
    void point(const float* offset, float* out, Cell& at) const {
        float jitter[kMaxDims];
        for (int i = 0; i < n; ++i) {
            at.at[i] = cell[i] + offset[i];
            at.index[i] = int32_t(uint32_t(index[i]) + uint32_t(int32_t(offset[i])));
        }
        point_of(t, n, at, jitter);
        for (int i = 0; i < n; ++i) out[i] = offset[i] + jitter[i] * randomness;
    }
};

float dot(int n, const float* a, const float* b) {
    float s = a[0] * b[0];
    for (int i = 1; i < n; ++i) s += a[i] * b[i];
    return s;
}

// The distance from coord to the nearest border between cells (Distance to Edge): the
// nearest point by squared distance, then the least distance to the bisectors between
// it and each other point (1D: the midpoints with the two neighbours).
float edge_distance(const Texture& t, int n, const float* coord, float randomness) {
    const Around a(t, n, coord, randomness);
    Cell at{};
    if (n == 1) {
        float p[3];
        for (int k = 0; k < 3; ++k) {
            const float offset = float(k - 1);
            a.point(&offset, &p[k], at);
        }
        return std::min(std::abs((p[1] + p[0]) / 2.0f - a.local[0]), std::abs((p[1] + p[2]) / 2.0f - a.local[0]));
    }
    float closest[kMaxDims] = {0, 0, 0, 0}, least = FLT_MAX;
    auto to_point = [&](const float* offset, float* v) {
        a.point(offset, v, at);
        for (int i = 0; i < n; ++i) v[i] -= a.local[i];
    };
    each_neighbour(n, 1, [&](const float* offset) {
        float v[kMaxDims];
        to_point(offset, v);
        const float d = dot(n, v, v);
        if (d < least) {
            least = d;
            std::copy(v, v + n, closest);
        }
    });
    least = FLT_MAX;
    each_neighbour(n, 1, [&](const float* offset) {
        float v[kMaxDims], across[kMaxDims], middle[kMaxDims];
        to_point(offset, v);
        for (int i = 0; i < n; ++i) across[i] = v[i] - closest[i];
        const float len2 = dot(n, across, across);
        if (len2 > 0.0001f) {
            const float len = std::sqrt(len2);
            for (int i = 0; i < n; ++i) {
                middle[i] = (closest[i] + v[i]) / 2.0f;
                across[i] /= len;
            }
            least = std::min(least, dot(n, middle, across));
        }
    });
    return least;
}

// Half the distance from the nearest point to its own nearest (N-Sphere Radius), by
// the straight distance whatever the metric.
float sphere_radius(const Texture& t, int n, const float* coord, float randomness) {
    const Around a(t, n, coord, randomness);
    auto distance = [&](const float* p, const float* q) {
        if (n == 1) return std::abs(p[0] - q[0]);
        float d[kMaxDims];
        for (int i = 0; i < n; ++i) d[i] = p[i] - q[i];
        return std::sqrt(dot(n, d, d));
    };
    float closest[kMaxDims] = {0, 0, 0, 0}, closest_offset[kMaxDims] = {0, 0, 0, 0}, least = FLT_MAX;
    Cell at{};
    each_neighbour(n, 1, [&](const float* offset) {
        float p[kMaxDims];
        a.point(offset, p, at);
        const float d = distance(p, a.local);
        if (d < least) {
            least = d;
            std::copy(p, p + n, closest);
            std::copy(offset, offset + n, closest_offset);
        }
    });
    least = FLT_MAX;
    float next[kMaxDims] = {0, 0, 0, 0};
    each_neighbour(n, 1, [&](const float* offset) {
        if (std::all_of(offset, offset + n, [](float x) { return x == 0.0f; })) return;
        float moved[kMaxDims], p[kMaxDims];
        for (int i = 0; i < n; ++i) moved[i] = offset[i] + closest_offset[i];
        a.point(moved, p, at);
        const float d = distance(closest, p);
        if (d < least) {
            least = d;
            std::copy(p, p + n, next);
        }
    });
    return distance(next, closest) / 2.0f;
}

// One octave of the feature at coord.
Octave octave_at(const Texture& t, int n, const float* coord, float randomness, float smoothness) {
    const Around a(t, n, coord, randomness);
    const float* cell = a.cell;
    const float* local = a.local;
    Octave o;
    float found[kMaxDims] = {0, 0, 0, 0};
    if (t.voronoi_feature == VoronoiFeature::SmoothF1 && smoothness != 0.0f) {
        float h = -1.0f, position[kMaxDims] = {0, 0, 0, 0};
        each_neighbour(n, 2, [&](const float* offset) {
            float p[kMaxDims], color[3];
            Cell at;
            a.point(offset, p, at);
            const float d = metric_distance(t, n, p, local);
            h = h == -1.0f ? 1.0f : smooth01(0.5f + 0.5f * (o.distance - d) / smoothness);
            float correction = smoothness * h * (1.0f - h);
            o.distance = mix(o.distance, d, h) - correction;
            correction /= 1.0f + 3.0f * smoothness;
            if (t.voronoi_output == VoronoiOutput::Color) {   // (125 colour hashes only where they are read)
                color_of(t, n, at, color);
                for (int c = 0; c < 3; ++c) o.color[c] = mix(o.color[c], color[c], h) - correction;
            }
            for (int i = 0; i < n; ++i) position[i] = mix(position[i], p[i], h) - correction;
        });
        for (int i = 0; i < n; ++i) found[i] = cell[i] + position[i];
    } else {
        const bool second = t.voronoi_feature == VoronoiFeature::F2;
        float d1 = FLT_MAX, d2 = FLT_MAX, p1[kMaxDims] = {0, 0, 0, 0}, p2[kMaxDims] = {0, 0, 0, 0};
        // (both start at this cell, as Cycles' offsets start at 0: where no distance is finite,
        // Minkowski with exponent 0, the colour is this cell's)
        Cell c1{}, c2{};
        for (int i = 0; i < n; ++i) {
            c1.at[i] = c2.at[i] = cell[i];
            c1.index[i] = c2.index[i] = a.index[i];
        }
        each_neighbour(n, 1, [&](const float* offset) {
            float p[kMaxDims];
            Cell at{};
            a.point(offset, p, at);
            const float d = metric_distance(t, n, p, local);
            if (d < d1) {
                d2 = d1;
                std::copy(p1, p1 + kMaxDims, p2);
                c2 = c1;
                d1 = d;
                std::copy(p, p + n, p1);
                c1 = at;
            } else if (second && d < d2) {
                d2 = d;
                std::copy(p, p + n, p2);
                c2 = at;
            }
        });
        o.distance = second ? d2 : d1;
        const float* p = second ? p2 : p1;
        color_of(t, n, second ? c2 : c1, o.color);
        for (int i = 0; i < n; ++i) found[i] = p[i] + cell[i];
    }
    // (1D: its coordinate is w; 2D and 3D: x, y, z; 4D all four)
    if (n == 1) o.position[3] = found[0];
    else for (int i = 0; i < n; ++i) o.position[i] = found[i];
    return o;
}

// Distance to Edge over 1 + detail octaves, as Cycles 4.0 and later take them (each
// octave's distance, divided by its scale, lowers the least so far by its amplitude;
// normalized by the largest distance so blended).
float edge_octaves(const Texture& t, int n, const float* coord, float detail, float roughness, float randomness) {
    const float largest = 0.5f + 0.5f * randomness;
    float amplitude = 1.0f, max_amplitude = largest, octave_scale = 1.0f, distance = 8.0f;
    const bool single = detail == 0.0f || roughness == 0.0f;
    for (int i = 0; i <= int(std::ceil(detail)); ++i) {
        float at[kMaxDims];
        for (int a = 0; a < n; ++a) at[a] = coord[a] * octave_scale;
        const float d = edge_distance(t, n, at, randomness);
        if (single) {
            distance = d;
            break;
        }
        if (float(i) <= detail) {
            max_amplitude = mix(max_amplitude, largest / octave_scale, amplitude);
            distance = mix(distance, std::min(distance, d / octave_scale), amplitude);
            octave_scale *= t.lacunarity;
            amplitude *= roughness;
        } else {
            const float rest = detail - std::floor(detail);
            if (rest != 0.0f) {
                max_amplitude = mix(max_amplitude, mix(max_amplitude, largest / octave_scale, amplitude), rest);
                const float lowered = mix(distance, std::min(distance, d / octave_scale), amplitude);
                distance = mix(distance, std::min(distance, lowered), rest);
            }
        }
    }
    return t.normalize ? distance / max_amplitude : distance;
}

}  // namespace

Rgba voronoi_color(const Texture& t, const Vec3& point) {
    const int n = t.dimensions;
    const float scale = t.scale;
    const float detail = std::min(std::max(t.detail, 0.0f), 15.0f);
    const float roughness = std::min(std::max(t.roughness, 0.0f), 1.0f);
    const float randomness = std::min(std::max(t.randomness, 0.0f), 1.0f);
    const float smoothness = std::min(std::max(t.smoothness / 2.0f, 0.0f), 0.5f);
    float coord[kMaxDims];
    pattern_coords(t, point, coord);
    auto grey = [](float v) {
        const float x = std::isfinite(v) ? v : 0.0f;
        return Rgba{Vec3(x, x, x), 1};
    };
    // (these two features give only their own output; Cycles sets the others to 0)
    if (t.voronoi_feature == VoronoiFeature::NSphereRadius)
        return grey(t.voronoi_output == VoronoiOutput::Radius ? sphere_radius(t, n, coord, randomness) : 0.0f);
    if (t.voronoi_feature == VoronoiFeature::DistanceToEdge)
        return grey(t.voronoi_output == VoronoiOutput::Distance ? edge_octaves(t, n, coord, detail, roughness, randomness)
                                                               : 0.0f);
    if (t.voronoi_output == VoronoiOutput::Radius) return grey(0.0f);
    // The octaves, as Cycles 4.0 and later sum them (fBM's sum, the positions blended).
    Octave out;
    float amplitude = 1.0f, max_amplitude = 0.0f, octave_scale = 1.0f;
    const bool single = detail == 0.0f || roughness == 0.0f;
    for (int i = 0; i <= int(std::ceil(detail)); ++i) {
        float at[kMaxDims];
        for (int a = 0; a < n; ++a) at[a] = coord[a] * octave_scale;
        const Octave o = octave_at(t, n, at, randomness, smoothness);
        if (single) {
            max_amplitude = 1.0f;
            out = o;
            break;
        }
        if (float(i) <= detail) {
            max_amplitude += amplitude;
            out.distance += o.distance * amplitude;
            for (int c = 0; c < 3; ++c) out.color[c] += o.color[c] * amplitude;
            for (int a = 0; a < kMaxDims; ++a)
                out.position[a] = mix(out.position[a], o.position[a] / octave_scale, amplitude);
            octave_scale *= t.lacunarity;
            amplitude *= roughness;
        } else {
            const float rest = detail - std::floor(detail);
            if (rest != 0.0f) {
                max_amplitude = mix(max_amplitude, max_amplitude + amplitude, rest);
                out.distance = mix(out.distance, out.distance + o.distance * amplitude, rest);
                for (int c = 0; c < 3; ++c) out.color[c] = mix(out.color[c], out.color[c] + o.color[c] * amplitude, rest);
                for (int a = 0; a < kMaxDims; ++a)
                    out.position[a] = mix(out.position[a], mix(out.position[a], o.position[a] / octave_scale, amplitude), rest);
            }
        }
    }
    if (t.normalize) {
        // The largest distance a point can lie from its nearest (twice that for F2).
        const float half = 0.5f + 0.5f * randomness;
        float reach = half;
        if (n > 1) {
            const float zero[kMaxDims] = {0, 0, 0, 0}, corner[kMaxDims] = {half, half, half, half};
            reach = metric_distance(t, n, zero, corner);
        }
        if (t.voronoi_feature == VoronoiFeature::F2) reach *= 2.0f;
        out.distance /= max_amplitude * reach;
        for (float& c : out.color) c /= max_amplitude;
    }
    for (float& p : out.position) p = scale != 0.0f ? p / scale : 0.0f;
    switch (t.voronoi_output) {
    case VoronoiOutput::Distance: return grey(out.distance);
    case VoronoiOutput::Color: return Rgba{Vec3(out.color[0], out.color[1], out.color[2]), 1};
    case VoronoiOutput::Position: return Rgba{Vec3(out.position[0], out.position[1], out.position[2]), 1};
    case VoronoiOutput::W: return grey(out.position[3]);
    case VoronoiOutput::Radius: break;
    }
    return grey(0);
}

}  // namespace gw
