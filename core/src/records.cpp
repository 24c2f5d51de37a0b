// Validation of the Material, Light and Camera records where they enter the
// core, in the precision the core computes in (float32): a value that is
// valid in Python's float64 but rounds to something invalid is refused here.
#include <stdexcept>

#include "camera.h"
#include "lights.h"
#include "material.h"
#include "text.h"

namespace gw {
namespace {

std::string show(double v) { return format_number(v, 9); }
std::string show(const Vec3& v) { return "(" + show(v.x) + ", " + show(v.y) + ", " + show(v.z) + ")"; }

[[noreturn]] void refuse(const std::string& where, const char* field, const std::string& what) {
    throw std::invalid_argument(where + "." + field + " " + what);
}
void need_finite(const std::string& where, const char* field, const Vec3& v) {
    if (!finite3(v)) refuse(where, field, "has a non-finite component: " + show(v));
}
void need_finite(const std::string& where, const char* field, double v) {
    if (!std::isfinite(v)) refuse(where, field, "must be finite, got " + show(v));
}
void need_at_least(const std::string& where, const char* field, double v, double lo) {
    need_finite(where, field, v);
    if (v < lo) refuse(where, field, "must be >= " + show(lo) + ", got " + show(v));
}

}  // namespace

void validate_material(const Material& m, const std::string& where) {
    need_finite(where, "color", m.color);
    need_finite(where, "kd", m.kd);
    need_finite(where, "ks", m.ks);
    need_finite(where, "transmittance", m.transmittance);
    need_finite(where, "mirror", m.mirror);
    need_finite(where, "emission", m.emission);
    need_at_least(where, "shininess", m.shininess, 0);
    need_at_least(where, "roughness", m.roughness, 0);
    need_finite(where, "ior", m.ior);
    if (!(m.ior > 0)) refuse(where, "ior", "must be > 0, got " + show(m.ior));
}

void prepare_light(Light& l, const std::string& where) {
    if (!enum_valid(l.kind)) refuse(where, "kind", "is not a light kind");
    need_finite(where, "position", l.position);
    need_finite(where, "color", l.color);
    need_finite(where, "axis_u", l.axis_u);
    need_finite(where, "axis_v", l.axis_v);
    need_finite(where, "direction", l.direction);
    need_at_least(where, "radius", l.radius, 0);
    need_at_least(where, "size", l.size[0], 0);
    need_at_least(where, "size", l.size[1], 0);
    need_at_least(where, "angle", l.angle, 0);
    need_finite(where, "spot_size", l.spot_size);
    need_finite(where, "spot_blend", l.spot_blend);
    if (!(l.spot_blend >= 0 && l.spot_blend <= 1)) refuse(where, "spot_blend", "must be in [0, 1], got " + show(l.spot_blend));
    const bool directed = l.kind == LightKind::Sun || l.kind == LightKind::Spot || l.kind == LightKind::Rect ||
                          l.kind == LightKind::Disk;
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
    const Vec3 fwd = c.target - c.eye;   // as the camera computes it, in float
    if (!finite3(fwd) || (fwd.x == 0 && fwd.y == 0 && fwd.z == 0))
        refuse(where, "target", "coincides with Camera.eye in float32 " + show(c.eye) +
                                   ": the camera has no viewing direction");
    const Vec3d f(fwd), u(c.up);
    if (!(length(cross(f, u)) > 1e-12 * length(f) * length(u)))
        refuse(where, "up", "is parallel to the viewing direction (or zero): " + show(c.up));
    if (c.width < 1 || c.height < 1)
        refuse(where, "width", "and Camera.height must be at least 1, got " + std::to_string(c.width) + " x " +
                                  std::to_string(c.height));
    if (int64_t(c.width) * int64_t(c.height) > (int64_t(1) << 28))
        refuse(where, "width", "x Camera.height = " + std::to_string(int64_t(c.width) * c.height) +
                                  " pixels: more than the limit of 2^28");
    if (!(c.fov > 0 && c.fov < 180))
        refuse(where, "fov", "must be in (0, 180) degrees after rounding to float32, got " + show(c.fov));
    // Neighbouring pixels must get different ray directions in float32.
    const double half = std::tan(double(c.fov) * kPi / 360.0);
    if (!(2.0 * half / double(std::max(c.width, c.height)) >= 1e-6))
        refuse(where, "fov", "= " + show(c.fov) + " degrees is too narrow for float32 ray directions at " +
                             std::to_string(std::max(c.width, c.height)) + " pixels");
    need_at_least(where, "aperture", c.aperture, 0);
    need_finite(where, "focus_distance", c.focus_distance);
    if (!(c.focus_distance > 0)) refuse(where, "focus_distance", "must be > 0, got " + show(c.focus_distance));
    need_finite(where, "shift", c.shift[0]);
    need_finite(where, "shift", c.shift[1]);
    need_at_least(where, "hither", c.hither, 0);
}

}  // namespace gw
