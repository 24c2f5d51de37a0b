// The diffuse light of an environment image: its irradiance E(n) as nine
// spherical-harmonic coefficients per colour (Ramamoorthi & Hanrahan, "An
// Efficient Representation for Irradiance Environment Maps", 2001). The
// radiance is projected on the real harmonics up to order 2 and convolved with
// the clamped cosine (factors pi, 2 pi / 3, pi / 4 for orders 0, 1, 2); the
// nine numbers keep E within a few percent of the exact integral for smooth
// skies (the convolution leaves little above order 2). at(n) returns E(n) / pi,
// the radiance a white Lambertian surface facing n sends back, so a uniform
// environment of radiance L gives L, as Whitted's ambient term does.
#pragma once
#include "math.h"
#include "texture.h"

namespace gw {

struct Irradiance {
    Vec3 c[9]{};   // order 0, then 1 (y, z, x), then 2 (xy, yz, 3z^2 - 1, xz, x^2 - y^2), times the basis constants
    // E(n) / pi for a unit normal n, clamped at 0 (the truncated series can
    // dip below 0 opposite a small bright source such as a sun).
    Vec3 at(const Vec3& n) const;
};

// The irradiance of texture `t` over `img` as an equirectangular environment
// (Blender's mapping, equirect_uv), times `strength`: every texel once,
// weighted by its exact solid angle.
Irradiance environment_irradiance(const Image& img, const Texture& t, float strength);

}  // namespace gw
