// The world record: what the scene's surroundings contribute besides the
// background colour. Bound to Python field by field as gridwalk._core.World.
//
// ambient: Whitted's ambient term I_a. Every surface adds color * kd * ambient,
// the light a diffuse surface receives from a uniform world if nothing blocked
// it (no occlusion: Whitted's model has no ambient occlusion). Blender's world
// colour x strength lights a diffuse surface with exactly that in Cycles when
// the surface sees the whole sky.
// environment: a texture (equirectangular) that rays which miss everything see,
// times environment_strength; -1 = none (they see the background colour).
// environment_rotation: the image is looked up along R d for a direction d
// (R row-major, a rotation): Blender's Mapping node rotating an environment.
// environment_light: surfaces also get the environment's diffuse light: the
// irradiance its image x environment_strength sends on their shading normal
// (irradiance.h), also without occlusion, added to the ambient term. Blender's
// image worlds set it (a sky over dark ground lights roofs, not floors' undersides).
// transparent: camera rays that miss see nothing (RGB 0 with alpha 0, a
// premultiplied transparent film, Blender's Film > Transparent); mirror and
// refraction rays still see the background or environment.
// inset: a texture showing a small part of the environment in detail (a Sky
// Texture's sun, a few texels of the environment wide), -1 = none: rays that miss
// see it instead of the environment within the square |x / z|, |y / z| <
// inset_extent of the frame inset_frame (rows: the x, y and z axes, orthonormal,
// in the environment image's frame; z the square's centre), its texture's u along
// x and v along y. Lighting still reads the environment alone, so the inset must
// show the same light: it only adds the detail the environment's texels blur.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "math.h"

namespace gw {

struct World {
    Vec3 ambient{0, 0, 0};
    int32_t environment = -1;
    float environment_strength = 1;
    std::array<float, 9> environment_rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
    bool environment_light = false;
    bool transparent = false;
    int32_t inset = -1;
    std::array<float, 9> inset_frame{1, 0, 0, 0, 1, 0, 0, 0, 1};
    float inset_extent = 0;
};

// R d and R^T d for a row-major 3 x 3 matrix R.
inline Vec3 rotate(const std::array<float, 9>& R, const Vec3& d) {
    return Vec3(R[0] * d.x + R[1] * d.y + R[2] * d.z, R[3] * d.x + R[4] * d.y + R[5] * d.z,
                R[6] * d.x + R[7] * d.y + R[8] * d.z);
}
inline Vec3 rotate_back(const std::array<float, 9>& R, const Vec3& d) {
    return Vec3(R[0] * d.x + R[3] * d.y + R[6] * d.z, R[1] * d.x + R[4] * d.y + R[7] * d.z,
                R[2] * d.x + R[5] * d.y + R[8] * d.z);
}

// Throws std::invalid_argument naming the field (the texture index is checked by the scene).
void validate_world(const World& w);

}  // namespace gw
