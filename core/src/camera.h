// The camera: perspective, orthographic or one of Cycles' panoramic
// projections (equirectangular, three fisheyes, mirror ball, cube map face,
// central cylindrical), with an optional thin lens (depth of field), lens
// shift, pixel aspect, near and far clipping and mirroring.
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
    // The aperture's shape: 0 (or fewer than 3) a disc, else a regular polygon of `blades`
    // corners at the aperture's radius, turned by blade_rotation (radians; at 0 an edge faces
    // the image's right); aperture_ratio > 1 narrows it across (an anamorphic lens' bokeh).
    int blades = 0;
    float blade_rotation = 0, aperture_ratio = 1;
    std::array<float, 2> shift{0, 0};     // in units of the image plane's larger side; a panorama's: of the unit square
    std::array<float, 2> longitude{-float(kPi), float(kPi)};         // equirectangular: left, right edge (radians)
    std::array<float, 2> latitude{-float(kPi / 2), float(kPi / 2)};  // equirectangular: bottom, top edge
    // Panoramas: the part (u0, u1, v0, v1) of the projection's unit square
    // that the image spans, left to right and bottom to top (Cycles' panorama
    // viewplane, before the shift: a final render's is the unit square).
    std::array<float, 4> window{0, 1, 0, 1};
    float fisheye_fov = float(kPi);        // fisheyes: the widest angle across the view axis (radians)
    float fisheye_lens = 10.5f;            // equisolid: focal length, mm
    std::array<float, 2> sensor{36, 24};   // equisolid and polynomial: the image's size on the sensor, mm
    std::array<float, 5> polynomial{-1.1735e-5f, -0.0199887f, -3.3525e-6f, 3.0993e-6f, -2.6065e-8f};   // k0..k4
    std::array<float, 2> cylinder_height{-1, 1};   // central cylindrical: bottom, top edge at distance 1
    float hither = 0;                     // near clip: rays start this far along the view axis
    // Camera texture coordinates are measured from the point this far along
    // the view axis from the eye (0: the eye). An orthographic viewport view
    // moves its eye back to its near plane and sets this to the view point.
    float origin_ahead = 0;
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
        lon_ = Span(c.longitude);
        lat_ = Span(c.latitude);
        aperture_ = c.aperture;
        focus_ = c.focus_distance;
        blades_ = c.blades >= 3 ? c.blades : 0;
        blade_rotation_ = c.blade_rotation;
        inv_ratio_ = 1.0f / c.aperture_ratio;
        hither_ = c.hither;
        origin_ahead_ = c.origin_ahead;
        yon_ = c.yon;
        panorama_ = projection_ != Projection::Perspective && projection_ != Projection::Orthographic;
        pano_shift_ = c.shift;
        window_u_ = Span({c.window[0], c.window[1]});
        window_v_ = Span({c.window[2], c.window[3]});
        cylinder_ = Span(c.cylinder_height);
        fisheye_fov_ = c.fisheye_fov;
        fisheye_lens_ = c.fisheye_lens;
        sensor_ = c.sensor;
        poly_ = c.polynomial;
    }
    // Image position (px, py) in pixels from the top-left corner; lens sample
    // (lu, lv) in [0,1)^2 (ignored for a pinhole). A panorama's position that
    // shows nothing (outside a fisheye's circle) gets no ray: a zero direction
    // (none()), which the pixel counts as black and opaque, as Cycles does
    // (also on a transparent film).
    Ray generate(float px, float py, float lu, float lv) const {
        Ray r;
        r.o = eye_;
        Vec3 d, lens_u = right_, lens_v = up_;
        if (panorama_) {
            const float u = window_u_.at(px / float(width_)) + pano_shift_[0];
            const float v = window_v_.at(1.0f - py / float(height_)) + pano_shift_[1];
            Vec3 p;   // the direction in panorama space: x forward, y left, z up
            // (no ray, too, where the direction overflows: a position far outside the
            // square, a shift or window of 1e19)
            if (!panorama_direction(u, v, p) || !finite3(p)) {
                r.d = Vec3();
                r.tmin = r.tmax = 0;
                return r;
            }
            d = normalize(fwd_ * p.x - right_ * p.y + up_ * p.z);
            if (aperture_ > 0) lens_across(d, lens_u, lens_v);
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
            aperture_point(lu, lv, dx, dy);
            const Vec3 lens = lens_u * (dx * aperture_) + lens_v * (dy * aperture_);
            r.o = r.o + lens;
            d = d * focus_ - lens;           // through the point on the focal plane (a panorama's: sphere)
        }
        r.d = normalize(d);
        if (panorama_) {                     // clipped by spheres around the eye
            r.tmin = hither_;
            r.tmax = yon_;
        } else {                             // clipped by planes across the view axis
            r.tmin = hither_ > 0 ? hither_ / dot(r.d, fwd_) : 0.0f;
            if (yon_ < kInf) r.tmax = yon_ / dot(r.d, fwd_);
        }
        return r;
    }
    // Cycles' Camera texture coordinates: the point in camera space, x right, y
    // up, z forward along the view axis (the camera's axes without its scale),
    // from the eye, or from origin_ahead along the view axis.
    Vec3 camera_point(const Vec3& p) const {
        const Vec3 c = eye_point(p);
        return Vec3(c.x, c.y, c.z - origin_ahead_);
    }
    // The point in camera space from the eye itself, whatever origin_ahead says.
    Vec3 eye_point(const Vec3& p) const {
        const Vec3 d = p - eye_;
        return Vec3(dot(d, right_), dot(d, up_), dot(d, fwd_));
    }
    // Cycles' Window texture coordinates: the point's place in the image, (0, 0)
    // its bottom-left corner and (1, 1) its top-right, z = 0; through the
    // perspective division as Cycles divides (a point behind the eye lands
    // mirrored, one on the eye's plane at infinity). A panorama's: where its
    // direction from the eye lies in the projection's unit square (panorama_uv),
    // as Cycles' direction_to_panorama gives it.
    Vec3 window_point(const Vec3& p) const {
        const Vec3 c = eye_point(p);   // (projected from the eye: origin_ahead moves Camera coordinates only)
        if (panorama_) {
            float u, v;
            panorama_uv(Vec3(c.z, -c.x, c.y), u, v);   // (panorama space: x forward, y left, z up)
            return Vec3(u, v, 0.0f);
        }
        const bool ortho = projection_ == Projection::Orthographic;
        const float x = ortho ? c.x : c.x / c.z, y = ortho ? c.y : c.y / c.z;
        return Vec3(0.5f + 0.5f * (x - shift_x_) / half_w_, 0.5f + 0.5f * (y - shift_y_) / half_h_, 0.0f);
    }
    // Where the direction p (panorama space, any length) lies in the projection's
    // unit square: the inverse of panorama_direction, extended past the edges
    // (a fisheye's angle beyond its field of view, a cube face's sides).
    void panorama_uv(const Vec3& p, float& u, float& v) const {
        const float len = length(p);
        if (!(len > 0) || !std::isfinite(len)) {
            u = v = 0;
            return;
        }
        const Vec3 d = p * (1.0f / len);
        const float across = std::sqrt(d.y * d.y + d.z * d.z);   // sin of the angle from the view axis
        switch (projection_) {
        case Projection::Equirectangular:
            u = (std::atan2(-d.y, d.x) - lon_.start) / lon_.size;
            v = (std::atan2(d.z, std::sqrt(d.x * d.x + d.y * d.y)) - lat_.start) / lat_.size;
            return;
        case Projection::CentralCylindrical:
            u = (std::atan2(-d.y, d.x) - lon_.start) / lon_.size;
            v = (d.z / std::sqrt(d.x * d.x + d.y * d.y) - cylinder_.start) / cylinder_.size;
            return;
        case Projection::CubemapFace:
            u = 0.5f - std::atan2(d.y, d.x) * float(2 / kPi);
            v = 0.5f + std::atan2(d.z, d.x) * float(2 / kPi);
            return;
        case Projection::MirrorBall: {
            // The ball's normal halves the turn from the view (ball y: back) to the ray:
            // n ~ ball - (0, 1, 0), with ball = (-d.y, -d.x, d.z).
            Vec3 n(-d.y, -d.x - 1.0f, d.z);
            const float nl = length(n);
            n = nl > 0 ? n * (1.0f / nl) : Vec3(0, -1, 0);
            u = 0.5f * (n.x + 1.0f);
            v = 0.5f * (n.z + 1.0f);
            return;
        }
        default: {   // the fisheyes: the radius in the image for the angle theta from the view axis
            const float theta = std::atan2(across, d.x);
            const float cx = across > 0 ? -d.y / across : 0.0f, sy = across > 0 ? d.z / across : 0.0f;
            if (projection_ == Projection::FisheyeEquidistant) {
                const float r = theta / (fisheye_fov_ * 0.5f);
                u = 0.5f * (r * cx + 1.0f);
                v = 0.5f * (r * sy + 1.0f);
                return;
            }
            float r;
            if (projection_ == Projection::FisheyeEquisolid) {
                r = 2.0f * fisheye_lens_ * std::sin(theta * 0.5f);
            } else {   // the polynomial's radius for theta, by Newton's method from its linear term
                auto angle = [&](float x) { return -(poly_[0] + x * (poly_[1] + x * (poly_[2] + x * (poly_[3] + x * poly_[4])))); };
                auto slope = [&](float x) { return -(poly_[1] + x * (2 * poly_[2] + x * (3 * poly_[3] + x * 4 * poly_[4]))); };
                r = poly_[1] != 0 ? -(theta + poly_[0]) / poly_[1] : 0.0f;
                for (int i = 0; i < 16 && std::isfinite(r); ++i) {
                    const float s = slope(r);
                    if (!(std::abs(s) > 0)) break;
                    r -= (angle(r) - theta) / s;
                }
            }
            u = r * cx / sensor_[0] + 0.5f;
            v = r * sy / sensor_[1] + 0.5f;
            return;
        }
        }
    }
    // Whether generate() gave no ray (a fisheye's corner).
    static bool none(const Ray& r) { return r.d.x == 0 && r.d.y == 0 && r.d.z == 0; }
    // The axis the Depth pass measures along: the view axis (a panorama: the ray).
    Vec3 depth_axis(const Ray& r) const { return panorama_ ? r.d : fwd_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    // A point of the unit aperture for the lens sample (lu, lv), as Cycles samples it: the
    // disc, or the polygon's corner lu picks, its triangle to the centre sampled uniformly;
    // then narrowed across by the ratio.
    void aperture_point(float lu, float lv, float& x, float& y) const {
        if (blades_ == 0) {
            concentric_disk(lu, lv, x, y);
        } else {
            const float n = float(blades_);
            const float corner = std::min(std::floor(lu * n), n - 1.0f);
            const float s = std::sqrt(std::max(lu * n - corner, 0.0f));   // the triangle's weights
            const float b = lv * s, a = 1.0f - s;
            const float half = float(kPi) / n;   // the corners lie half a sector either side of its middle
            const float px = (a + b) * std::cos(half), py = (a - b) * std::sin(half);
            const float turn = blade_rotation_ + corner * 2.0f * half;
            const float c = std::cos(turn), sn = std::sin(turn);
            x = c * px - sn * py;
            y = sn * px + c * py;
        }
        x *= inv_ratio_;
    }
    // A panorama's lens plane across the ray d, oriented as Cycles orients it: its x along
    // the panorama's x axis (forward; a mirror ball's: right) made perpendicular to d,
    // its y = d x that (turned back for the mirror ball, whose axes are a mirror image).
    void lens_across(const Vec3& d, Vec3& lens_u, Vec3& lens_v) const {
        const bool ball = projection_ == Projection::MirrorBall;
        const Vec3 axis = ball ? right_ : fwd_;
        const Vec3 u = axis - d * dot(axis, d);
        const float len = length(u);
        if (!(len > 1e-6f)) {   // (along the axis itself, where Cycles' frame is undefined)
            basis(d, lens_u, lens_v);
            return;
        }
        lens_u = u * (1.0f / len);
        lens_v = ball ? cross(lens_u, d) : cross(d, lens_u);
    }

    // The panorama's direction at (u, v) of its unit square, in panorama
    // space (x forward, y left, z up), as Cycles computes it for each type;
    // false where the projection shows nothing.
    bool panorama_direction(float u, float v, Vec3& p) const {
        switch (projection_) {
        case Projection::Equirectangular: {
            const float lon = lon_.at(u), lat = lat_.at(v);
            const float c = std::cos(lat);
            p = Vec3(c * std::cos(lon), -c * std::sin(lon), std::sin(lat));
            return true;
        }
        case Projection::CentralCylindrical: {
            const float lon = lon_.at(u);
            p = Vec3(std::cos(lon), -std::sin(lon), cylinder_.at(v));
            return true;
        }
        case Projection::CubemapFace:
            p = Vec3(1.0f, std::tan((0.5f - u) * float(kPi / 2)), std::tan((v - 0.5f) * float(kPi / 2)));
            return true;
        case Projection::MirrorBall: {
            // The ball's normal n = (2u - 1, -sqrt(...), 2v - 1) in the ball's frame (its y
            // towards the camera's back); the view ray (0, -1, 0) reflected about it, then
            // turned into panorama space (ball x: right, y: back, z: up).
            const float nx = 2.0f * u - 1.0f, nz = 2.0f * v - 1.0f, rr = nx * nx + nz * nz;
            if (rr > 1.0f) return false;
            const float ny = -std::sqrt(std::max(1.0f - rr, 0.0f));
            const float k = -2.0f * ny;   // 2 (n . i), i = (0, -1, 0)
            const Vec3 ball(k * nx, k * ny + 1.0f, k * nz);
            p = Vec3(-ball.y, -ball.x, ball.z);
            return true;
        }
        default: {   // the fisheyes: an angle theta from the view axis for a radius r in the image
            const bool equidistant = projection_ == Projection::FisheyeEquidistant;
            // (equidistant: the unit square's ellipse; the others: mm on the sensor)
            const float x = equidistant ? 2.0f * u - 1.0f : (u - 0.5f) * sensor_[0];
            const float y = equidistant ? 2.0f * v - 1.0f : (v - 0.5f) * sensor_[1];
            const float r = std::sqrt(x * x + y * y);
            float theta;
            if (equidistant) {
                if (r > 1.0f) return false;
                theta = r * fisheye_fov_ * 0.5f;
            } else if (projection_ == Projection::FisheyeEquisolid) {
                if (r > 2.0f * fisheye_lens_ * std::sin(fisheye_fov_ * 0.25f)) return false;
                theta = 2.0f * std::asin(std::min(r / (2.0f * fisheye_lens_), 1.0f));
            } else {
                theta = -(poly_[0] + r * (poly_[1] + r * (poly_[2] + r * (poly_[3] + r * poly_[4]))));
                if (!(std::abs(theta) <= fisheye_fov_ * 0.5f)) return false;   // (NaN too)
            }
            // (the centre: Cycles' direction there, with cos(phi) = 0 and sin(phi) = 1)
            const float cx = r != 0.0f ? x / r : 0.0f, sy = r != 0.0f ? y / r : 1.0f;
            const float st = std::sin(theta);
            p = Vec3(std::cos(theta), -cx * st, sy * st);
            return true;
        }
        }
    }

    // A range [start, start + size] of a panorama's setting, read at a fraction t of it.
    struct Span {
        float start = 0, size = 1;
        Span() = default;
        explicit Span(const std::array<float, 2>& ends) : start(ends[0]), size(ends[1] - ends[0]) {}
        float at(float t) const { return start + t * size; }
    };

    int width_, height_;
    Projection projection_;
    Vec3 eye_;
    Vec3d eye_d_;
    Vec3 fwd_, right_, up_;
    float half_h_, half_w_, shift_x_, shift_y_, aperture_, focus_, hither_, yon_, blade_rotation_, inv_ratio_;
    float origin_ahead_;
    int blades_;
    Span lon_, lat_, window_u_, window_v_, cylinder_;
    bool panorama_ = false;
    float fisheye_fov_, fisheye_lens_;
    std::array<float, 2> sensor_, pano_shift_;
    std::array<float, 5> poly_;
};

}  // namespace gw
