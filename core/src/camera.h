// Perspective camera with an optional thin lens (depth of field).
#pragma once
#include "ray.h"
#include "scene.h"
#include "sampler.h"

namespace gw {

class Camera {
public:
    explicit Camera(const CameraDesc& c) : width_(c.width), height_(c.height), eye_(c.eye) {
        fwd_ = normalize(c.target - c.eye);
        right_ = normalize(cross(fwd_, c.up));
        up_ = cross(right_, fwd_);
        half_h_ = std::tan(float(c.fov_deg * kPi / 360.0));
        half_w_ = half_h_ * float(c.width) / float(c.height);
        const float big = 2.0f * std::max(half_w_, half_h_);   // shift is in units of the larger side
        shift_x_ = c.shift_x * big;
        shift_y_ = c.shift_y * big;
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
