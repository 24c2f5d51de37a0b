// Scene construction (with input validation) and per-primitive geometry queries.
#include "scene.h"

#include <stdexcept>

namespace gw {
namespace {

[[noreturn]] void bad(const std::string& msg) { throw std::invalid_argument(msg); }

void check_finite(const std::vector<float>& a, int width, const char* name) {
    for (size_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(a[i]))
            bad(std::string(name) + "[" + std::to_string(i / width) + "] has a non-finite value (NaN or Inf)");
}

void check_ids(const std::vector<int32_t>& ids, size_t limit, int width, const char* name, const char* what) {
    for (size_t i = 0; i < ids.size(); ++i)
        if (ids[i] < 0 || size_t(ids[i]) >= limit)
            bad(std::string(name) + "[" + std::to_string(i / width) + "] = " + std::to_string(ids[i]) +
                " is out of range: " + what + " has " + std::to_string(limit) + " entries");
}

Vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }

}  // namespace

Scene::Scene(std::vector<float> vertices, std::vector<int32_t> triangles, std::vector<float> normals,
             std::vector<int32_t> tri_materials, std::vector<float> sphere_centers,
             std::vector<float> sphere_radii, std::vector<int32_t> sphere_materials,
             std::vector<float> cone_base, std::vector<float> cone_apex, std::vector<float> cone_base_radius,
             std::vector<float> cone_apex_radius, std::vector<int32_t> cone_materials,
             const std::vector<float>& materials, const std::vector<float>& lights,
             const std::vector<float>& camera, Vec3 background)
    : verts_(std::move(vertices)), normals_(std::move(normals)), tris_(std::move(triangles)),
      tri_mat_(std::move(tri_materials)), radii_(std::move(sphere_radii)),
      sphere_mat_(std::move(sphere_materials)), cone_mat_(std::move(cone_materials)), background_(background) {
    // --- shapes -------------------------------------------------------------
    if (verts_.size() % 3) bad("vertices must have shape (N, 3)");
    if (tris_.size() % 3) bad("triangles must have shape (M, 3)");
    const size_t nv = verts_.size() / 3, nt = tris_.size() / 3, ns = radii_.size(), nc = cone_base_radius.size();
    if (!normals_.empty() && normals_.size() != verts_.size()) bad("normals must have the same shape as vertices");
    if (tri_mat_.empty()) tri_mat_.assign(nt, 0);
    if (tri_mat_.size() != nt) bad("triangle_materials must have one entry per triangle");
    if (sphere_centers.size() != 3 * ns) bad("sphere_centers must have shape (K, 3) matching sphere_radii (K,)");
    if (sphere_mat_.empty()) sphere_mat_.assign(ns, 0);
    if (sphere_mat_.size() != ns) bad("sphere_materials must have one entry per sphere");
    if (cone_base.size() != 3 * nc || cone_apex.size() != 3 * nc || cone_apex_radius.size() != nc)
        bad("cylinder_base/cylinder_apex (J,3) and cylinder_base_radius/cylinder_apex_radius (J,) must agree");
    if (cone_mat_.empty()) cone_mat_.assign(nc, 0);
    if (cone_mat_.size() != nc) bad("cylinder_materials must have one entry per cylinder");
    if (nt + ns + nc == 0) bad("the scene is empty: no triangles, spheres or cylinders");
    if (nt + ns + nc >= (size_t(1) << 31)) bad("too many primitives (limit 2^31)");
    if (materials.empty() || materials.size() % kMaterialWidth) bad("materials table must have shape (>=1, 12)");
    if (lights.size() % kLightWidth) bad("lights table must have shape (L, 24)");
    if (camera.size() != kCameraWidth) bad("camera record must have 20 values");

    // --- values -------------------------------------------------------------
    check_finite(verts_, 3, "vertices");
    check_finite(normals_, 3, "normals");
    check_finite(sphere_centers, 3, "sphere_centers");
    check_finite(radii_, 1, "sphere_radii");
    check_finite(cone_base, 3, "cylinder_base");
    check_finite(cone_apex, 3, "cylinder_apex");
    check_finite(cone_base_radius, 1, "cylinder_base_radius");
    check_finite(cone_apex_radius, 1, "cylinder_apex_radius");
    check_finite(materials, kMaterialWidth, "materials");
    check_finite(lights, kLightWidth, "lights");
    check_finite(camera, kCameraWidth, "camera");
    check_ids(tris_, nv, 3, "triangles", "vertices");
    const size_t nm = materials.size() / kMaterialWidth;
    check_ids(tri_mat_, nm, 1, "triangle_materials", "materials");
    check_ids(sphere_mat_, nm, 1, "sphere_materials", "materials");
    check_ids(cone_mat_, nm, 1, "cylinder_materials", "materials");
    for (size_t i = 0; i < ns; ++i)
        if (radii_[i] < 0) bad("sphere_radii[" + std::to_string(i) + "] is negative");

    tri_verts_.resize(3 * nt);
    for (size_t i = 0; i < 3 * nt; ++i) tri_verts_[i] = vert(tris_[i]);
    centers_.resize(ns);
    for (size_t i = 0; i < ns; ++i) centers_[i] = v3(&sphere_centers[3 * i]);
    cones_.resize(nc);
    for (size_t i = 0; i < nc; ++i) {
        const Vec3d b(v3(&cone_base[3 * i])), a(v3(&cone_apex[3 * i]));
        const double h = length(a - b);
        const double r0 = std::abs(double(cone_base_radius[i])), r1 = std::abs(double(cone_apex_radius[i]));
        if (!(h > 0)) bad("cylinder_apex[" + std::to_string(i) + "] coincides with cylinder_base");
        cones_[i] = ConeData{b, (a - b) / h, h, r0, (r1 - r0) / h};
    }
    materials_.resize(nm);
    for (size_t i = 0; i < nm; ++i) {
        const float* m = &materials[i * kMaterialWidth];
        materials_[i] = Material{v3(m), m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10]};
        if (!(m[7] > 0)) bad("materials[" + std::to_string(i) + "] has ior <= 0");
    }
    for (size_t i = 0; i < lights.size() / kLightWidth; ++i) {
        const float* l = &lights[i * kLightWidth];
        Light L;
        if (!(l[0] >= 0 && l[0] <= 5) || float(int(l[0])) != l[0])
            bad("lights[" + std::to_string(i) + "] has an unknown kind");
        const int k = int(l[0]);
        L.kind = LightKind(k);
        L.position = v3(l + 1);
        L.color = v3(l + 4);
        L.axis_u = normalize(v3(l + 7));
        L.axis_v = normalize(v3(l + 10));
        L.direction = normalize(v3(l + 13));
        L.radius = std::abs(l[16]);
        L.width = std::abs(l[17]);
        L.height = std::abs(l[18]);
        L.angle = std::abs(l[19]);
        L.spot_cos = l[20];
        L.spot_blend = l[21];
        L.inverse_square = l[22] != 0;
        if ((L.kind == LightKind::Sun || L.kind == LightKind::Spot || L.kind == LightKind::Rect ||
             L.kind == LightKind::Disk) && length(v3(l + 13)) == 0)
            bad("lights[" + std::to_string(i) + "] needs a non-zero direction");
        lights_.push_back(L);
    }
    const float* c = camera.data();
    if (!(c[10] >= 1 && c[11] >= 1 && c[10] * c[11] <= float(1 << 28)))
        bad("camera resolution must be at least 1x1 and at most 2^28 pixels");
    camera_ = CameraDesc{v3(c), v3(c + 3), v3(c + 6), c[9], int(c[10]), int(c[11]), c[12], c[13], c[14], c[15], c[16]};
    if (camera_.width < 1 || camera_.height < 1) bad("camera resolution must be at least 1x1");

    // Coordinates (and extents) within +-1e30 keep every box, distance and
    // grid cell computation finite in float.
    constexpr float kLimit = 1e30f;
    for (size_t i = 0; i < num_prims(); ++i) {
        const Bounds pb = prim_bounds(i);
        if (!(std::max(std::abs(pb.lo.x), std::max(std::abs(pb.lo.y), std::abs(pb.lo.z))) <= kLimit &&
              std::max(std::abs(pb.hi.x), std::max(std::abs(pb.hi.y), std::abs(pb.hi.z))) <= kLimit)) {
            const char* what = kind_of(i) == PrimKind::Triangle ? "triangles"
                             : kind_of(i) == PrimKind::Sphere   ? "sphere_radii"
                                                                 : "cylinder_base_radius";
            bad(std::string(what) + "[" + std::to_string(local_index(i)) +
                "]: the primitive extends beyond +-1e30, which the core cannot represent");
        }
        bounds_.grow(pb);
    }
}

bool Scene::intersect_quadric(size_t prim, const RayPre& r, Hit& hit) const {
    float t;
    const size_t s = prim - num_triangles();
    if (s < num_spheres()) {
        if (!intersect_sphere(r, centers_[s], radii_[s], hit.t, t)) return false;
    } else if (!intersect_cone(r, cones_[s - num_spheres()], hit.t, t)) {
        return false;
    }
    hit.t = t;
    hit.prim = int32_t(prim);
    hit.u = hit.v = 0;
    return true;
}

Bounds Scene::prim_bounds(size_t prim) const {
    Bounds b;
    switch (kind_of(prim)) {
    case PrimKind::Triangle: {
        const int32_t* f = &tris_[3 * prim];
        b.grow(vert(f[0])); b.grow(vert(f[1])); b.grow(vert(f[2]));
        break;
    }
    case PrimKind::Sphere: {
        const size_t s = local_index(prim);
        const Vec3 r(radii_[s], radii_[s], radii_[s]);
        // Round outwards so the float box contains the exact sphere.
        b.lo = centers_[s] - r; b.hi = centers_[s] + r;
        for (int a = 0; a < 3; ++a) { b.lo[a] = next_down(b.lo[a]); b.hi[a] = next_up(b.hi[a]); }
        break;
    }
    default: {
        const ConeData& c = cones_[local_index(prim)];
        const Vec3d ends[2] = {c.base, c.base + c.axis * c.height};
        const double rad[2] = {c.r0, c.r0 + c.k * c.height};
        for (int e = 0; e < 2; ++e)
            for (int a = 0; a < 3; ++a) {
                const double ext = rad[e] * std::sqrt(std::max(0.0, 1.0 - c.axis[a] * c.axis[a]));
                b.lo[a] = std::min(b.lo[a], next_down(float(ends[e][a] - ext)));
                b.hi[a] = std::max(b.hi[a], next_up(float(ends[e][a] + ext)));
            }
    }
    }
    return b;
}

Vec3 Scene::geometric_normal(const RayPre& r, const Hit& hit) const {
    const size_t prim = size_t(hit.prim);
    switch (kind_of(prim)) {
    case PrimKind::Triangle: {
        const int32_t* f = &tris_[3 * prim];
        const Vec3 v0 = vert(f[0]);
        return normalize(cross(vert(f[1]) - v0, vert(f[2]) - v0));
    }
    case PrimKind::Sphere: {
        const size_t s = local_index(prim);
        const Vec3d p = r.od + r.dd * double(hit.t);
        return Vec3(normalize(p - Vec3d(centers_[s])));
    }
    default: {
        const ConeData& c = cones_[local_index(prim)];
        const Vec3d w = r.od + r.dd * double(hit.t) - c.base;
        const double s = dot(w, c.axis);
        const Vec3d perp = w - c.axis * s;
        return Vec3(normalize(perp - c.axis * (c.k * (c.r0 + c.k * s))));
    }
    }
}

SurfacePoint Scene::surface(const RayPre& r, const Hit& hit) const {
    SurfacePoint sp;
    const size_t prim = size_t(hit.prim);
    sp.ng = geometric_normal(r, hit);
    switch (kind_of(prim)) {
    case PrimKind::Triangle: {
        const int32_t* f = &tris_[3 * prim];
        const float b0 = 1.0f - hit.u - hit.v;
        const Vec3 v0 = vert(f[0]), v1 = vert(f[1]), v2 = vert(f[2]);
        const Vec3 a = v0 * b0, b = v1 * hit.u, c = v2 * hit.v;
        sp.p = a + b + c;
        // Error bound of the barycentric interpolation (pbrt-v3 3.9.3).
        sp.p_err = (vabs(a) + vabs(b) + vabs(c)) * gamma_bound(7);
        sp.material = tri_mat_[prim];
        sp.ns = sp.ng;
        if (!normals_.empty()) {
            auto nrm = [&](int32_t i) {
                const size_t k = 3 * size_t(i);
                return Vec3{normals_[k], normals_[k + 1], normals_[k + 2]};
            };
            const Vec3 n = nrm(f[0]) * b0 + nrm(f[1]) * hit.u + nrm(f[2]) * hit.v;
            const float len = length(n);
            if (len > 0 && std::isfinite(len)) {
                sp.ns = n / len;
                if (dot(sp.ns, sp.ng) < 0) sp.ng = -sp.ng;   // the normals define the outside
            }
        }
        break;
    }
    case PrimKind::Sphere: {
        const size_t s = local_index(prim);
        const Vec3d c(centers_[s]);
        const Vec3d n(sp.ng);
        const Vec3d p = c + n * double(radii_[s]);   // re-projected onto the surface
        sp.p = Vec3(p);
        // p is exact to double precision, then rounded once to float.
        sp.p_err = vabs(sp.p) * gamma_bound(3);
        sp.ns = sp.ng;
        sp.material = sphere_mat_[s];
        break;
    }
    default: {
        // Re-project onto the surface in double (as for spheres): o + t d
        // carries t's rounding error along d, which no per-axis bound on |p| covers.
        const size_t k = local_index(prim);
        const ConeData& c = cones_[k];
        const Vec3d w = r.od + r.dd * double(hit.t) - c.base;
        const double s = std::min(std::max(dot(w, c.axis), 0.0), c.height);
        Vec3d radial = w - c.axis * dot(w, c.axis);
        const double len = length(radial);
        radial = len > 0 ? radial / len : radial;
        sp.p = Vec3(c.base + c.axis * s + radial * (c.r0 + c.k * s));
        sp.p_err = vabs(sp.p) * gamma_bound(3);
        sp.ns = sp.ng;
        sp.material = cone_mat_[k];
    }
    }
    if (!finite3(sp.ng) || length(sp.ng) == 0) sp.ng = sp.ns = normalize(-r.ray.d);
    return sp;
}

size_t Scene::memory_bytes() const {
    return verts_.size() * 4 + tri_verts_.size() * 12 + normals_.size() * 4 + tris_.size() * 4 + tri_mat_.size() * 4 +
           centers_.size() * 12 + radii_.size() * 4 + sphere_mat_.size() * 4 + cones_.size() * sizeof(ConeData) +
           cone_mat_.size() * 4;
}

}  // namespace gw
