// What the texture coordinates that depend on the view need to know
// (Blender's Texture Coordinate node's Normal, Camera, Window and
// Reflection outputs): the camera's frame, and the ray that found the hit.
#pragma once
#include "math.h"
#include "surface_point.h"

namespace gw {

// The camera's axes and image plane, as the Camera that renders sets them
// (Camera::frame). Camera space is Cycles': x right, y up, z forward along the
// view axis (the camera object's axes with its scale left out, z turned to
// face the view), from the eye.
struct ViewFrame {
    Vec3 eye{0, 0, 0}, right{1, 0, 0}, up{0, 1, 0}, fwd{0, 0, 1};
    float half_w = 1, half_h = 1, shift_x = 0, shift_y = 0;
    bool orthographic = false;
    bool panorama = false;

    Vec3 camera_point(const Vec3& p) const {
        const Vec3 d = p - eye;
        return Vec3(dot(d, right), dot(d, up), dot(d, fwd));
    }
    // Cycles' Window coordinates: the point's place in the image, (0, 0) its
    // bottom-left corner and (1, 1) its top-right, z = 0; through the
    // perspective division as Cycles divides (a point behind the eye lands
    // mirrored, one on the eye's plane at infinity). A panorama's: (0, 0, 0)
    // (not computed; the exporter says so).
    Vec3 window_point(const Vec3& p) const {
        if (panorama) return Vec3(0, 0, 0);
        const Vec3 c = camera_point(p);
        const float x = orthographic ? c.x : c.x / c.z, y = orthographic ? c.y : c.y / c.z;
        return Vec3(0.5f + 0.5f * (x - shift_x) / half_w, 0.5f + 0.5f * (y - shift_y) / half_h, 0.0f);
    }
};

// The ray's side of a hit: the point p, wi towards where the ray came from, n
// the shading normal before normal and bump maps and ng the geometric normal,
// both turned over where the ray meets the back of the surface (as Cycles
// turns N and Ng on a back face, the back by the winding: the exporter winds
// a mirrored object's triangles so that theirs faces out), and the frame of
// the camera rendering (null: none, those coordinates read 0).
struct TextureView {
    Vec3 p{0, 0, 0};
    Vec3 wi{0, 0, 1};
    Vec3 n{0, 0, 1};
    Vec3 ng{0, 0, 1};
    bool backfacing = false;
    const ViewFrame* frame = nullptr;

    // At sp, met by a ray along d (any length).
    static TextureView at(const SurfacePoint& sp, const Vec3& d, const ViewFrame* frame) {
        TextureView v;
        v.p = sp.p;
        const float len = length(d);
        v.wi = len > 0 && std::isfinite(len) ? d * (-1.0f / len) : sp.ng;
        const Vec3 winding = sp.turned ? -sp.ng : sp.ng;
        v.backfacing = dot(winding, v.wi) < 0;
        const Vec3 n = sp.mapped ? sp.unmapped : sp.ns;
        v.n = v.backfacing ? -n : n;
        v.ng = v.backfacing ? -winding : winding;
        v.frame = frame;
        return v;
    }
    // Cycles' Reflection coordinates: wi mirrored about n, in world space.
    Vec3 reflection() const { return n * (2.0f * dot(n, wi)) - wi; }
};

}  // namespace gw
