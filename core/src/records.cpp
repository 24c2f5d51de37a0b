// Validation of the Material, Light and Camera records where they enter the
// core, in the precision the core computes in (float32): a value that is
// valid in Python's float64 but rounds to something invalid is refused here.
#include <limits>
#include <stdexcept>

#include "camera.h"
#include "lights.h"
#include "material.h"
#include "world.h"
#include "text.h"

namespace gw {
namespace {

std::string show(double v) { return format_number(v, 9); }
template <class T>
std::string show(const V3<T>& v) { return "(" + show(v.x) + ", " + show(v.y) + ", " + show(v.z) + ")"; }

[[noreturn]] void refuse(const std::string& where, const char* field, const std::string& what) {
    throw std::invalid_argument(where + "." + field + " " + what);
}
void need_finite(const std::string& where, const char* field, const Vec3& v) {
    if (!finite3(v)) refuse(where, field, "has a non-finite component: " + show(v));
}
void need_finite(const std::string& where, const char* field, const Vec3d& v) {
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
        refuse(where, field, "has a non-finite component: " + show(v));
}
void need_finite(const std::string& where, const char* field, double v) {
    if (!std::isfinite(v)) refuse(where, field, "must be finite, got " + show(v));
}
void need_at_least(const std::string& where, const char* field, double v, double lo) {
    need_finite(where, field, v);
    if (v < lo) refuse(where, field, "must be >= " + show(lo) + ", got " + show(v));
}

// Reflected and emitted light cannot be negative: a negative colour or weight
// gave negative pixels (clipped to black in a PNG, kept in .npy).
void need_non_negative(const std::string& where, const char* field, const Vec3& v) {
    need_finite(where, field, v);
    if (v.x < 0 || v.y < 0 || v.z < 0) refuse(where, field, "must have no negative component, got " + show(v));
}

}  // namespace

void validate_material(const Material& m, const std::string& where) {
    need_non_negative(where, "color", m.color);
    need_at_least(where, "kd", m.kd, 0);
    need_at_least(where, "ks", m.ks, 0);
    need_at_least(where, "transmittance", m.transmittance, 0);
    need_at_least(where, "mirror", m.mirror, 0);
    need_finite(where, "metallic", m.metallic);
    if (!(m.metallic >= 0 && m.metallic <= 1)) refuse(where, "metallic", "must be in [0, 1], got " + show(m.metallic));
    need_non_negative(where, "metal_color", m.metal_color);
    need_at_least(where, "emission", m.emission, 0);
    need_at_least(where, "shininess", m.shininess, 0);
    need_at_least(where, "roughness", m.roughness, 0);
    need_finite(where, "ior", m.ior);
    if (!(m.ior > 0)) refuse(where, "ior", "must be > 0, got " + show(m.ior));
    need_non_negative(where, "emission_color", m.emission_color);
    need_finite(where, "alpha", m.alpha);
    if (!(m.alpha >= 0 && m.alpha <= 1)) refuse(where, "alpha", "must be in [0, 1], got " + show(m.alpha));
    need_at_least(where, "normal_strength", m.normal_strength, 0);
    need_at_least(where, "bump_strength", m.bump_strength, 0);
    need_finite(where, "bump_distance", m.bump_distance);
    // Texture indices are checked against the scene's textures by the scene.
    const std::pair<const char*, int32_t> textures[] = {{"color_texture", m.color_texture},
        {"roughness_texture", m.roughness_texture}, {"metallic_texture", m.metallic_texture},
        {"alpha_texture", m.alpha_texture}, {"normal_texture", m.normal_texture},
        {"emission_texture", m.emission_texture}, {"bump_texture", m.bump_texture}};
    for (const auto& [field, index] : textures)
        if (index < -1) refuse(where, field, "must be a texture index or -1 (none), got " + std::to_string(index));
}

// Whether a row-major 3 x 3 matrix's rows are orthonormal (to 1e-3).
static bool orthonormal_rows(const std::array<float, 9>& R) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double dot_ij = double(R[3 * i]) * R[3 * j] + double(R[3 * i + 1]) * R[3 * j + 1] +
                                  double(R[3 * i + 2]) * R[3 * j + 2];
            if (std::abs(dot_ij - (i == j ? 1.0 : 0.0)) > 1e-3) return false;
        }
    return true;
}

void validate_world(const World& w) {
    need_finite("World", "ambient", w.ambient);
    need_finite("World", "environment_strength", w.environment_strength);
    for (float x : w.environment_rotation)
        if (!std::isfinite(x)) refuse("World", "environment_rotation", "has a non-finite value");
    const auto& R = w.environment_rotation;
    if (!orthonormal_rows(R))
        refuse("World", "environment_rotation", "must be a rotation (orthonormal rows, row-major 3 x 3)");
    const double det = double(R[0]) * (double(R[4]) * R[8] - double(R[5]) * R[7]) -
                       double(R[1]) * (double(R[3]) * R[8] - double(R[5]) * R[6]) +
                       double(R[2]) * (double(R[3]) * R[7] - double(R[4]) * R[6]);
    if (det < 0) refuse("World", "environment_rotation", "must be a rotation, not a reflection (determinant -1)");
    if (w.environment < -1)
        refuse("World", "environment", "must be a texture index or -1 (none), got " + std::to_string(w.environment));
    if (w.inset < -1) refuse("World", "inset", "must be a texture index or -1 (none), got " + std::to_string(w.inset));
    if (!(w.inset_extent >= 0) || !std::isfinite(w.inset_extent))
        refuse("World", "inset_extent", "must be a finite number >= 0");
    for (float x : w.inset_frame)
        if (!std::isfinite(x)) refuse("World", "inset_frame", "has a non-finite value");
    if (!orthonormal_rows(w.inset_frame)) refuse("World", "inset_frame", "must have orthonormal rows (row-major 3 x 3)");
}

void prepare_light(Light& l, const std::string& where) {
    if (!enum_valid(l.kind)) refuse(where, "kind", "is not a light kind");
    need_finite(where, "position", l.position);
    need_non_negative(where, "color", l.color);   // (a negative light added nothing, silently)
    need_finite(where, "axis_u", l.axis_u);
    need_finite(where, "axis_v", l.axis_v);
    need_finite(where, "direction", l.direction);
    need_at_least(where, "radius", l.radius, 0);
    need_at_least(where, "size", l.size[0], 0);
    need_at_least(where, "size", l.size[1], 0);
    need_at_least(where, "angle", l.angle, 0);
    if (l.kind == LightKind::Sun && l.angle > float(kPi))   // (Blender's range: 0 to 180 degrees)
        throw std::invalid_argument(where + ".angle = " + std::to_string(l.angle) +
                                    ": a sun's angular diameter is at most pi (180 degrees)");
    need_finite(where, "spot_size", l.spot_size);
    need_finite(where, "spot_blend", l.spot_blend);
    if (!(l.spot_blend >= 0 && l.spot_blend <= 1)) refuse(where, "spot_blend", "must be in [0, 1], got " + show(l.spot_blend));
    const bool directed = l.kind == LightKind::Sun || l.kind == LightKind::Spot || is_flat(l);
    if (directed && length(l.direction) == 0)
        refuse(where, "direction", std::string("must be non-zero for a ") + enum_id(l.kind) + " light");
    l.axis_u = normalize(l.axis_u);
    l.axis_v = normalize(l.axis_v);
    l.direction = normalize(l.direction);
    l.spot_cos = float(std::cos(0.5 * l.spot_size));
}

void validate_camera(const CameraDesc& c) {
    const std::string where = "Camera";
    need_finite(where, "eye", c.eye);
    need_finite(where, "target", c.target);
    need_finite(where, "up", c.up);
    if (!finite3(Vec3(c.eye)) || !finite3(Vec3(c.target)))
        refuse(where, !finite3(Vec3(c.eye)) ? "eye" : "target", "lies beyond the float32 range");
    if (!enum_valid(c.projection)) refuse(where, "projection", "is not a projection");
    const Vec3 fwd(c.target - c.eye);   // as the camera computes it: the difference in double, then float
    if (!finite3(fwd) || (fwd.x == 0 && fwd.y == 0 && fwd.z == 0))
        refuse(where, "target", "coincides with Camera.eye " + show(c.eye) + " (or lies too close to it for "
                                "float32): the camera has no viewing direction");
    const Vec3d f(fwd), u(c.up);
    if (!(length(cross(f, u)) > 1e-12 * length(f) * length(u)))
        refuse(where, "up", "is parallel to the viewing direction (or zero): " + show(c.up));
    if (c.width < 1 || c.height < 1)
        refuse(where, "width", "and Camera.height must be at least 1, got " + std::to_string(c.width) + " x " +
                                  std::to_string(c.height));
    if (int64_t(c.width) * int64_t(c.height) > (int64_t(1) << 28))
        refuse(where, "width", "x Camera.height = " + std::to_string(int64_t(c.width) * c.height) +
                                  " pixels: more than the limit of 2^28");
    need_finite(where, "pixel_aspect", c.pixel_aspect);
    if (!(c.pixel_aspect >= 1e-4f && c.pixel_aspect <= 1e4f))
        refuse(where, "pixel_aspect", "must be in [1e-4, 1e4], got " + show(c.pixel_aspect));
    const int side = std::max(c.width, c.height);
    if (c.projection == Projection::Perspective) {
        if (!(c.fov > 0 && c.fov < 180))
            refuse(where, "fov", "must be in (0, 180) degrees after rounding to float32, got " + show(c.fov));
        // Neighbouring pixels must get different ray directions in float32.
        const double half = std::tan(double(c.fov) * kPi / 360.0);
        if (!(2.0 * half / double(side) >= 1e-6))
            refuse(where, "fov", "= " + show(c.fov) + " degrees is too narrow for float32 ray directions at " +
                                 std::to_string(side) + " pixels");
    } else if (c.projection == Projection::Orthographic) {
        need_finite(where, "ortho_height", c.ortho_height);
        if (!(c.ortho_height > 0)) refuse(where, "ortho_height", "must be > 0, got " + show(c.ortho_height));
        // Neighbouring pixels must get different ray origins in float32.
        const double reach = std::max({std::abs(c.eye.x), std::abs(c.eye.y), std::abs(c.eye.z)});
        const double pixel = double(c.ortho_height) / double(c.height) * std::min(1.0, double(c.pixel_aspect));
        if (!(pixel >= 2.0 * reach * double(std::numeric_limits<float>::epsilon())) || !(pixel > 1e-30))
            refuse(where, "ortho_height", "= " + show(c.ortho_height) + " is too small for float32 ray origins " +
                                          show(reach) + " from the origin at " + std::to_string(c.height) +
                                          " pixels");
    } else {   // a panorama
        auto need_range = [&](const char* field, float lo, float hi) {
            need_finite(where, field, lo);
            need_finite(where, field, hi);
            if (!(lo != hi))   // (reversed is allowed: a flipped image, as in Cycles)
                refuse(where, field, "must span a range (its two ends differ), got (" + show(lo) + ", " + show(hi) + ")");
            if (!std::isfinite(hi - lo))
                refuse(where, field, "spans more than float32 holds: (" + show(lo) + ", " + show(hi) + ")");
        };
        need_range("longitude", c.longitude[0], c.longitude[1]);
        need_range("latitude", c.latitude[0], c.latitude[1]);
        need_range("window", c.window[0], c.window[1]);
        need_range("window", c.window[2], c.window[3]);
        need_range("cylinder_height", c.cylinder_height[0], c.cylinder_height[1]);
        for (const float k : c.polynomial) need_finite(where, "polynomial", k);
        for (const float size : c.sensor) {
            need_finite(where, "sensor", size);
            if (!(size > 0)) refuse(where, "sensor", "sizes must be > 0 mm, got " + show(size));
        }
        need_finite(where, "fisheye_fov", c.fisheye_fov);
        if (!(c.fisheye_fov > 0)) refuse(where, "fisheye_fov", "must be > 0 radians, got " + show(c.fisheye_fov));
        need_finite(where, "fisheye_lens", c.fisheye_lens);
        if (!(c.fisheye_lens > 0)) refuse(where, "fisheye_lens", "must be > 0 mm, got " + show(c.fisheye_lens));
    }
    need_at_least(where, "aperture", c.aperture, 0);
    if (!(c.blades >= 0 && c.blades <= 64))
        refuse(where, "blades", "must be in [0, 64] (0: a round aperture), got " + std::to_string(c.blades));
    need_finite(where, "blade_rotation", c.blade_rotation);
    need_finite(where, "aperture_ratio", c.aperture_ratio);
    if (!(c.aperture_ratio >= 1e-3f && c.aperture_ratio <= 1e3f))
        refuse(where, "aperture_ratio", "must be in [1e-3, 1e3], got " + show(c.aperture_ratio));
    need_finite(where, "focus_distance", c.focus_distance);
    if (!(c.focus_distance > 0)) refuse(where, "focus_distance", "must be > 0, got " + show(c.focus_distance));
    need_finite(where, "shift", c.shift[0]);
    need_finite(where, "shift", c.shift[1]);
    need_at_least(where, "hither", c.hither, 0);
    need_finite(where, "origin_ahead", c.origin_ahead);
    if (std::isnan(c.yon) || !(c.yon > c.hither))
        refuse(where, "yon", "must be greater than Camera.hither (" + show(c.hither) + "), got " + show(c.yon));
}

}  // namespace gw
