// What shading and secondary rays need to know about a hit.
#pragma once
#include "math.h"

namespace gw {

struct SurfacePoint {
    Vec3 p;        // hit position
    Vec3 p_err;    // conservative absolute error bound of p, per axis
    Vec3 ng;       // geometric normal, unit, "outward" (winding / radial)
    Vec3 ns;       // shading normal, unit, same hemisphere as ng
    // ng was turned over to agree with the vertex normals: the triangle's winding faces the other way.
    bool turned = false;
    // Where a normal map tilted ns: the shading normal before it (oriented as
    // ng), for the bumps' shadowing of diffuse light.
    bool mapped = false;
    Vec3 unmapped;
    int material = 0;
};

}  // namespace gw
