// Perspective camera with an optional thin lens (depth of field).
#pragma once
#include <array>

#include "ray.h"
#include "sampler.h"

namespace gw {

// The camera record, bound to Python field by field as gridwalk._core.Camera
// (see gridwalk.Camera for the meaning of each field).
struct CameraDesc {
    Vec3 eye{0, -10, 0}, target, up{0, 0, 1};
    float fov = 45;                       // vertical field of view, degrees
    int width = 512, height = 512;
    float aperture = 0, focus_distance = 1;
    std::array<float, 2> shift{0, 0};     // in units of the image plane's larger side
    float hither = 0;
};

// Throws std::invalid_argument naming the field, for values the camera
// cannot use as float32 (the precision it computes in).
void validate_camera(const CameraDesc& c);

class Camera {
public:
    explicit Camera(const CameraDesc& c) : width_(c.width), height_(c.height), eye_(c.eye) {
        fwd_ = normalize(c.target - c.eye);
        right_ = normalize(cross(fwd_, c.up));
        up_ = cross(right_, fwd_);
        half_h_ = std::tan(float(c.fov * kPi / 360.0));
        half_w_ = half_h_ * float(c.width) / float(c.height);
        const float big = 2.0f * std::max(half_w_, half_h_);   // shift is in units of the larger side
        shift_x_ = c.shift[0] * big;
        shift_y_ = c.shift[1] * big;
        aperture_ = c.aperture;
        focus_ = c.focus_distance;
        hither_ = c.hither;
    }
    // Image position (px, py) in pixels from the top-left corner; lens sample
    // (lu, lv) in [0,1)^2 (ignored for a pinhole).
    Ray generate(float px, float py, float lu, float lv) const {
        const float x = (2.0f * px / float(width_) - 1.0f) * half_w_ + shift_x_;
        const float y = (1.0f - 2.0f * py / float(height_)) * half_h_ + shift_y_;
        Vec3 d = fwd_ + right_ * x + up_ * y;   // on the plane at distance 1
        Ray r;
        r.o = eye_;
        if (aperture_ > 0) {
            float dx, dy;
            concentric_disk(lu, lv, dx, dy);
            const Vec3 lens = right_ * (dx * aperture_) + up_ * (dy * aperture_);
            r.o = eye_ + lens;
            d = d * focus_ - lens;           // through the point on the focal plane
        }
        r.d = normalize(d);
        r.tmin = hither_ > 0 ? hither_ / dot(r.d, fwd_) : 0.0f;
        return r;
    }
    const Vec3& forward() const { return fwd_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_, height_;
    Vec3 eye_, fwd_, right_, up_;
    float half_h_, half_w_, shift_x_, shift_y_, aperture_, focus_, hither_;
};

}  // namespace gw
