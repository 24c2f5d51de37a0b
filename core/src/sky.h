// The clear sky's light, as Blender's Sky Texture computes its table
// (gridwalk.sky lays the table out and turns it into an environment).
//
// single_scattering: Nishita et al. 1993 as Cycles' Nishita sky (Blender 3.x-4.x;
// 5.0's Single Scattering): air, dust and ozone over 21 wavelengths, each view
// ray marched in 32 segments, each lit by the sun through the atmosphere above.
// multiple_scattering: Blender 5.0's Multiple Scattering sky (Garcia Linan's
// four-wavelength model): 64 segments per view ray, a transmittance table
// towards the sun, and a closed-form fit of the light scattered more than once
// plus the ground's bounce.
//
// Both take n unit view directions (x, y, z; z up) and give CIE XYZ radiance.
// The sun lies at azimuth 0 (+x side) for single_scattering and azimuth pi
// (-x side) for multiple_scattering, as the two tables are laid out.
#pragma once
#include <cstddef>

namespace gw {

struct SkyAtmosphere {
    float altitude = 0;      // metres (single) or kilometres (multiple) above the ground
    float air = 1, dust = 1, ozone = 1;   // density factors (1 = Earth's)
};

void sky_single_scattering(const float* views, size_t n, float sun_elevation, const SkyAtmosphere& a, float* xyz,
                           int threads);
// XYZ radiance of the sun's disc seen at `elevation`: its light through the
// atmosphere (the Earth not in the way) over the disc's solid angle.
void sky_sun(bool multiple, float elevation, float solid_angle, const SkyAtmosphere& a, float* xyz);
void sky_multiple_scattering(const float* views, size_t n, float sun_elevation, const SkyAtmosphere& a, float* xyz,
                             int threads);

}  // namespace gw
