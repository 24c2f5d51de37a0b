// The Whitted material record (NFF's `f r g b Kd Ks Shine T ior`, plus a
// mirror weight, a glossy roughness and an emission strength). Bound to
// Python field by field as gridwalk._core.Material.
#pragma once
#include <string>

#include "math.h"

namespace gw {

struct Material {
    Vec3 color{1, 1, 1};
    float kd = 0.8f, ks = 0, shininess = 32, transmittance = 0, ior = 1, mirror = 0, roughness = 0, emission = 0;
};

// Throws std::invalid_argument naming `where` (e.g. "materials[2]") and the field.
void validate_material(const Material& m, const std::string& where);

}  // namespace gw
