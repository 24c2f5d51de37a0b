// The diffuse light of an environment image, tabulated over normals.
//
// A RadianceMap averages the image (every texel once, weighted by its solid
// angle) into at most max_w x max_w / 2 cells of the same equirectangular
// layout. The Irradiance table integrates a map of at most 128 x 64 cells
// against the clamped cosine for 64 x 32 normal directions (the same layout)
// and interpolates between them bilinearly. Each entry is divided by the
// same sum over the cosine alone (pi, up to the cells' quadrature), so a
// uniform environment of radiance L gives exactly L, as Whitted's ambient
// term does. at(n) returns E(n) / pi, the radiance a white Lambertian surface
// facing n sends back. The table is exact for every environment up to the
// cells' size, suns included (a sun's light on faces turned away from it is
// 0, as it should be; nine spherical-harmonic coefficients, tried first, gave
// those faces 6% of it and rang around its terminator).
#pragma once
#include <vector>

#include "math.h"
#include "texture.h"

namespace gw {

// The band [z0, z1] (z = sin elevation) of row y of h in the equirectangular layout, row 0 at the bottom.
void elevation_band(int y, int h, double& z0, double& z1);

struct RadianceMap {
    int w = 0, h = 0;            // cells; row 0 at the bottom (as Image::texel)
    std::vector<Vec3> rgb;       // the mean radiance of each cell
    // Cell (x, y)'s solid angle and its centre's direction (equirect_uv's layout).
    double solid_angle(int y) const;
    Vec3 direction(int x, int y) const;
};

// The image of texture t (its colour, premultiplied as the texture says)
// times strength, in at most max_w x max_w / 2 cells.
RadianceMap radiance_map(const Image& img, const Texture& t, float strength, int max_w);
// The same map in at most max_w x max_w / 2 cells.
RadianceMap coarser(const RadianceMap& map, int max_w);
// The map's bright cells (a sun: luminance above 20 times the map's mean over
// the sphere) moved into `bright`, the rest left in `map` (those cells 0 there).
// Returns whether there were any.
bool split_bright(RadianceMap& map, RadianceMap& bright);

class Irradiance {
public:
    Irradiance() = default;
    explicit Irradiance(const RadianceMap& radiance);
    bool empty() const { return e_.empty(); }
    // E(n) / pi for a unit normal n.
    Vec3 at(const Vec3& n) const;

private:
    std::vector<Vec3> e_;   // kNormalW x kNormalH, row 0 at the bottom
    Vec3 south_, north_;    // at the poles (normals -z and +z), beyond the rows' centres
};

}  // namespace gw
