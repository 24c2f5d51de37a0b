// The camera: perspective, orthographic or equirectangular (panoramic)
// projection, with an optional thin lens (depth of field), lens shift, pixel
// aspect, near and far clipping and mirroring.
#pragma once
#include <array>

#include "enums.h"
#include "ray.h"
#include "sampler.h"

namespace gw {

// The camera record, bound to Python field by field as gridwalk._core.Camera
// (see gridwalk.Camera for the meaning of each field). eye and target are
// kept in double: a camera far from the origin keeps its viewing direction
// (float32 would round target - eye to a whole unit at 1e7).
struct CameraDesc {
    Vec3d eye{0, -10, 0}, target;
    Vec3 up{0, 0, 1};
    Projection projection = Projection::Perspective;
    float fov = 45;                       // perspective: vertical field of view, degrees
    float ortho_height = 2;               // orthographic: height of the view in scene units
    int width = 512, height = 512;
    float pixel_aspect = 1;               // a pixel's width / height
    float aperture = 0, focus_distance = 1;
    std::array<float, 2> shift{0, 0};     // in units of the image plane's larger side
    std::array<float, 2> longitude{-float(kPi), float(kPi)};         // equirectangular: left, right edge (radians)
    std::array<float, 2> latitude{-float(kPi / 2), float(kPi / 2)};  // equirectangular: bottom, top edge
    float hither = 0;                     // near clip: rays start this far along the view axis
    float yon = kInf;                     // far clip: rays end this far along the view axis
    bool mirror = false;                  // mirrored image (a camera with negative scale)
};

// Throws std::invalid_argument naming the field, for values the camera
// cannot use as float32 (the precision it computes in).
void validate_camera(const CameraDesc& c);

class Camera {
public:
    explicit Camera(const CameraDesc& c)
        : width_(c.width), height_(c.height), projection_(c.projection), eye_(c.eye), eye_d_(c.eye) {
        fwd_ = normalize(Vec3(c.target - c.eye));   // the difference in double, then float
        right_ = normalize(cross(fwd_, c.up));
        up_ = cross(right_, fwd_);
        if (c.mirror) right_ = -right_;
        half_h_ = projection_ == Projection::Orthographic ? 0.5f * c.ortho_height
                                                           : std::tan(float(c.fov * kPi / 360.0));
        half_w_ = half_h_ * (float(c.width) * c.pixel_aspect) / float(c.height);
        const float big = 2.0f * std::max(half_w_, half_h_);   // shift is in units of the larger side
        shift_x_ = c.shift[0] * big;
        shift_y_ = c.shift[1] * big;
        lon0_ = c.longitude[0];
        lon_span_ = c.longitude[1] - c.longitude[0];
        lat1_ = c.latitude[1];
        lat_span_ = c.latitude[1] - c.latitude[0];
        aperture_ = c.aperture;
        focus_ = c.focus_distance;
        hither_ = c.hither;
        yon_ = c.yon;
    }
    // Image position (px, py) in pixels from the top-left corner; lens sample
    // (lu, lv) in [0,1)^2 (ignored for a pinhole).
    Ray generate(float px, float py, float lu, float lv) const {
        Ray r;
        r.o = eye_;
        Vec3 d, lens_u = right_, lens_v = up_;
        if (projection_ == Projection::Equirectangular) {
            const float lon = lon0_ + px / float(width_) * lon_span_;
            const float lat = lat1_ - py / float(height_) * lat_span_;
            const float c = std::cos(lat);
            d = normalize(fwd_ * (c * std::cos(lon)) + right_ * (c * std::sin(lon)) + up_ * std::sin(lat));
            basis(d, lens_u, lens_v);   // the lens lies across the ray
        } else {
            const float x = (2.0f * px / float(width_) - 1.0f) * half_w_ + shift_x_;
            const float y = (1.0f - 2.0f * py / float(height_)) * half_h_ + shift_y_;
            if (projection_ == Projection::Perspective) {
                d = fwd_ + right_ * x + up_ * y;   // on the plane at distance 1
            } else {   // the image plane through the eye, offset in double (far from the origin)
                d = fwd_;
                r.o = Vec3(eye_d_ + Vec3d(right_) * double(x) + Vec3d(up_) * double(y));
            }
        }
        if (aperture_ > 0) {
            float dx, dy;
            concentric_disk(lu, lv, dx, dy);
            const Vec3 lens = lens_u * (dx * aperture_) + lens_v * (dy * aperture_);
            r.o = r.o + lens;
            d = d * focus_ - lens;           // through the point on the focal plane
        }
        r.d = normalize(d);
        if (projection_ == Projection::Equirectangular) {   // clipped by spheres around the eye
            r.tmin = hither_;
            r.tmax = yon_;
        } else {                                            // clipped by planes across the view axis
            r.tmin = hither_ > 0 ? hither_ / dot(r.d, fwd_) : 0.0f;
            if (yon_ < kInf) r.tmax = yon_ / dot(r.d, fwd_);
        }
        return r;
    }
    // The axis the Depth pass measures along: the view axis (a panorama: the ray).
    Vec3 depth_axis(const Ray& r) const { return projection_ == Projection::Equirectangular ? r.d : fwd_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_, height_;
    Projection projection_;
    Vec3 eye_;
    Vec3d eye_d_;
    Vec3 fwd_, right_, up_;
    float half_h_, half_w_, shift_x_, shift_y_, lon0_, lon_span_, lat1_, lat_span_, aperture_, focus_, hither_,
        yon_;
};

}  // namespace gw
