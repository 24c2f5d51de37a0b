// What the texture coordinates that depend on the view need to know
// (Blender's Texture Coordinate node's Normal, Camera, Window and
// Reflection outputs, its Geometry node's normals and Incoming): the camera
// that renders, and the ray that found the hit.
#pragma once
#include "camera.h"
#include "math.h"
#include "surface_point.h"

namespace gw {

// The ray's side of a hit: the point p, wi towards where the ray came from, n
// the shading normal before normal and bump maps and ng the geometric normal,
// both turned over where the ray meets the back of the surface (as Cycles
// turns N and Ng on a back face, the back by the winding: the exporter winds
// a mirrored object's triangles so that theirs faces out), and the frame of
// the camera rendering (Camera::camera_point, window_point; null: none, those
// coordinates read 0).
struct TextureView {
    Vec3 p{0, 0, 0};
    Vec3 wi{0, 0, 1};
    Vec3 n{0, 0, 1};
    Vec3 ng{0, 0, 1};
    bool backfacing = false;
    const Camera* camera = nullptr;

    // At sp, met by a ray along d (any length).
    static TextureView at(const SurfacePoint& sp, const Vec3& d, const Camera* camera) {
        TextureView v;
        v.p = sp.p;
        const float len = length(d);
        v.wi = len > 0 && std::isfinite(len) ? d * (-1.0f / len) : sp.ng;
        const Vec3 winding = sp.turned ? -sp.ng : sp.ng;
        v.backfacing = dot(winding, v.wi) < 0;
        const Vec3 n = sp.mapped ? sp.unmapped : sp.ns;
        v.n = v.backfacing ? -n : n;
        v.ng = v.backfacing ? -winding : winding;
        v.camera = camera;
        return v;
    }
    // Cycles' Reflection coordinates: wi mirrored about n, in world space.
    Vec3 reflection() const { return n * (2.0f * dot(n, wi)) - wi; }
};

}  // namespace gw
