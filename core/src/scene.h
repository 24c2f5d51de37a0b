// The scene as the core sees it: flat arrays of triangles, spheres and cones,
// materials, lights and a camera. Primitives share one global index space:
// [0, T) triangles, [T, T+S) spheres, [T+S, T+S+C) cones.
#pragma once
#include <string>
#include <vector>

#include "cone.h"
#include "ray.h"
#include "sphere.h"
#include "triangle.h"

namespace gw {

struct Material {
    Vec3 color{1, 1, 1};
    float kd = 0.8f, ks = 0, shininess = 32, transmittance = 0, ior = 1, mirror = 0, roughness = 0,
          emission = 0;
};
constexpr int kMaterialWidth = 12;

enum class LightKind : int { Point = 0, Sphere = 1, Rect = 2, Disk = 3, Sun = 4, Spot = 5 };
struct Light {
    LightKind kind = LightKind::Point;
    Vec3 position, color, axis_u, axis_v, direction;  // axis_u/v: unit; direction: unit
    float radius = 0, width = 0, height = 0, angle = 0, spot_cos = -1, spot_blend = 0;
    bool inverse_square = false;
};
constexpr int kLightWidth = 24;

struct CameraDesc {
    Vec3 eye, target, up;
    float fov_deg = 45;
    int width = 1, height = 1;
    float aperture = 0, focus_distance = 1, shift_x = 0, shift_y = 0, hither = 0;
};
constexpr int kCameraWidth = 20;

// Surface data at a hit, for shading and for spawning secondary rays.
struct SurfacePoint {
    Vec3 p;        // hit position
    Vec3 p_err;    // conservative absolute error bound of p, per axis
    Vec3 ng;       // geometric normal, unit, "outward" (winding / radial)
    Vec3 ns;       // shading normal, unit, same hemisphere as ng
    int material = 0;
};

struct Bounds {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    void grow(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void grow(const Bounds& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return !(lo.x <= hi.x); }
};

class Scene {
public:
    // Arrays are copied into the scene (one memcpy each); the caller's buffers
    // may be freed afterwards. Throws std::invalid_argument naming the array
    // and the first bad index.
    Scene(std::vector<float> vertices, std::vector<int32_t> triangles, std::vector<float> normals,
          std::vector<int32_t> tri_materials, std::vector<float> sphere_centers,
          std::vector<float> sphere_radii, std::vector<int32_t> sphere_materials,
          std::vector<float> cone_base, std::vector<float> cone_apex, std::vector<float> cone_base_radius,
          std::vector<float> cone_apex_radius, std::vector<int32_t> cone_materials,
          const std::vector<float>& materials, const std::vector<float>& lights,
          const std::vector<float>& camera, Vec3 background);

    size_t num_triangles() const { return tris_.size() / 3; }
    size_t num_spheres() const { return radii_.size(); }
    size_t num_cones() const { return cones_.size(); }
    size_t num_prims() const { return num_triangles() + num_spheres() + num_cones(); }
    PrimKind kind_of(size_t prim) const {
        if (prim < num_triangles()) return PrimKind::Triangle;
        if (prim < num_triangles() + num_spheres()) return PrimKind::Sphere;
        return PrimKind::Cone;
    }
    size_t local_index(size_t prim) const {
        if (prim < num_triangles()) return prim;
        if (prim < num_triangles() + num_spheres()) return prim - num_triangles();
        return prim - num_triangles() - num_spheres();
    }

    Bounds prim_bounds(size_t prim) const;
    const Bounds& bounds() const { return bounds_; }

    // Tests one primitive; on a hit nearer than hit.t, updates hit and returns true.
    // Triangles are tested inline (the hot path); quadrics out of line.
    inline bool intersect(size_t prim, const RayPre& r, Hit& hit) const;
    bool intersect_quadric(size_t prim, const RayPre& r, Hit& hit) const;
    SurfacePoint surface(const RayPre& r, const Hit& hit) const;
    Vec3 geometric_normal(const RayPre& r, const Hit& hit) const;

    const std::vector<Material>& materials() const { return materials_; }
    const std::vector<Light>& lights() const { return lights_; }
    const CameraDesc& camera() const { return camera_; }
    Vec3 background() const { return background_; }
    size_t memory_bytes() const;

private:
    Vec3 vert(int32_t i) const {
        const size_t k = 3 * size_t(i);
        return {verts_[k], verts_[k + 1], verts_[k + 2]};
    }

    std::vector<float> verts_, normals_;
    std::vector<Vec3> tri_verts_;   // 3 per triangle: the hot loop reads one contiguous record
    std::vector<int32_t> tris_, tri_mat_;
    std::vector<Vec3> centers_;
    std::vector<float> radii_;
    std::vector<int32_t> sphere_mat_;
    std::vector<ConeData> cones_;
    std::vector<int32_t> cone_mat_;
    std::vector<Material> materials_;
    std::vector<Light> lights_;
    CameraDesc camera_;
    Vec3 background_;
    Bounds bounds_;
};

__attribute__((always_inline)) inline bool Scene::intersect(size_t prim, const RayPre& r, Hit& hit) const {
    if (prim >= num_triangles()) return intersect_quadric(prim, r, hit);
    float t, u, v;
    if (!intersect_triangle(r, &tri_verts_[3 * prim].x, hit.t, t, u, v)) return false;
    hit.t = t;
    hit.prim = int32_t(prim);
    hit.u = u;
    hit.v = v;
    return true;
}

}  // namespace gw
