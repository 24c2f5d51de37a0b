// Scene construction (with input validation) and per-primitive geometry queries.
#include "scene.h"
#include "text.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <stdexcept>

namespace gw {
namespace {

[[noreturn]] void bad(const std::string& msg) { throw std::invalid_argument(msg); }

// (Both checks first pass over the whole array in a loop the compiler
// vectorises even for plain SSE2, or-ing a flag per entry, and look for the
// offending entry only when there is one: a scene of 7.2M triangles spent a
// fifth of its construction in the entry-by-entry checks.)
template <class Array>
void check_finite(const Array& a, int width, const char* name) {
    static_assert(sizeof(a[0]) == sizeof(uint32_t), "float arrays");
    uint32_t any = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        uint32_t bits;
        std::memcpy(&bits, &a[i], sizeof bits);
        any |= uint32_t((bits & 0x7F800000u) == 0x7F800000u);   // (an all-ones exponent: Inf or NaN)
    }
    if (!any) return;
    for (size_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(a[i]))
            bad(std::string(name) + "[" + std::to_string(i / width) + "] has a non-finite value (NaN or Inf)");
}

template <class Array>
void check_ids(const Array& ids, size_t limit, int width, const char* name, const char* what) {
    // An id is in range when, read as unsigned, it is below the limit (a negative one
    // reads as 2^31 or more; a limit of 2^31 or more admits every non-negative int32).
    const uint32_t below = uint32_t(std::min<size_t>(limit, size_t(1) << 31));
    uint32_t any = 0;
    for (size_t i = 0; i < ids.size(); ++i) any |= uint32_t(uint32_t(ids[i]) >= below);
    if (!any) return;
    for (size_t i = 0; i < ids.size(); ++i)
        if (ids[i] < 0 || size_t(ids[i]) >= limit)
            bad(std::string(name) + "[" + std::to_string(i / width) + "] = " + std::to_string(ids[i]) +
                " is out of range: " + what + " has " + std::to_string(limit) + " entries");
}

Vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }

}  // namespace

Scene::Scene(PooledVector<float> vertices, PooledVector<int32_t> triangles, PooledVector<float> normals,
             PooledVector<int32_t> tri_materials, std::vector<float> sphere_centers,
             std::vector<float> sphere_radii, std::vector<int32_t> sphere_materials,
             std::vector<float> cone_base, std::vector<float> cone_apex, std::vector<float> cone_base_radius,
             std::vector<float> cone_apex_radius, std::vector<int32_t> cone_materials,
             std::vector<Material> materials, std::vector<Light> lights, const CameraDesc& camera,
             Vec3 background, PooledVector<float> uvs, PooledVector<float> colors,
             std::vector<std::shared_ptr<const Image>> images, std::vector<Texture> textures, const World& world,
             PooledVector<float> generated, PooledVector<float> object_coords, PooledVector<float> object_normals)
    : verts_(std::move(vertices)), normals_(std::move(normals)), tris_(std::move(triangles)),
      tri_mat_(std::move(tri_materials)), radii_(std::move(sphere_radii)),
      sphere_mat_(std::move(sphere_materials)), cone_mat_(std::move(cone_materials)),
      materials_(std::move(materials)), lights_(std::move(lights)), camera_(camera), background_(background),
      uvs_(std::move(uvs)), colors_(std::move(colors)), generated_(std::move(generated)),
      object_coords_(std::move(object_coords)), object_normals_(std::move(object_normals)), images_(std::move(images)), textures_(std::move(textures)),
      world_(world) {
    // --- shapes -------------------------------------------------------------
    if (verts_.size() % 3) bad("vertices must have shape (N, 3)");
    if (tris_.size() % 3) bad("triangles must have shape (M, 3)");
    const size_t nv = verts_.size() / 3, nt = tris_.size() / 3, ns = radii_.size(), nc = cone_base_radius.size();
    nt_ = nt;
    ns_ = ns;
    nc_ = nc;
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
    if (materials_.empty()) bad("the scene needs at least one material");

    // --- values -------------------------------------------------------------
    check_finite(verts_, 3, "vertices");
    check_finite(normals_, 3, "normals");
    check_finite(sphere_centers, 3, "sphere_centers");
    check_finite(radii_, 1, "sphere_radii");
    check_finite(cone_base, 3, "cylinder_base");
    check_finite(cone_apex, 3, "cylinder_apex");
    check_finite(cone_base_radius, 1, "cylinder_base_radius");
    check_finite(cone_apex_radius, 1, "cylinder_apex_radius");
    check_ids(tris_, nv, 3, "triangles", "vertices");
    const size_t nm = materials_.size();
    check_ids(tri_mat_, nm, 1, "triangle_materials", "materials");
    check_ids(sphere_mat_, nm, 1, "sphere_materials", "materials");
    check_ids(cone_mat_, nm, 1, "cylinder_materials", "materials");
    for (size_t i = 0; i < ns; ++i)
        if (radii_[i] < 0) bad("sphere_radii[" + std::to_string(i) + "] is negative");

    // One padding corner at the end: the SIMD triangle test reads each
    // triangle's 9 floats as three rows of 4 (triangle_simd.inc).
    // The triangles' bounds are their corners' bounds (bounds_of, bounds.h).
    // (Written by index into a sized array, and boxed in a pass of its own that is
    // vectorised: push_back and Bounds::grow per corner took 3x the instructions.)
    tri_verts_.resize(3 * nt + 1);
    for (size_t i = 0; i < 3 * nt; ++i) tri_verts_[i] = vert(tris_[i]);
    const Bounds tri_bounds = bounds_of(tri_verts_.data(), 3 * nt);
    centers_.resize(ns);
    for (size_t i = 0; i < ns; ++i) centers_[i] = v3(&sphere_centers[3 * i]);
    cones_.resize(nc);
    for (size_t i = 0; i < nc; ++i) {
        const Vec3d b(v3(&cone_base[3 * i])), a(v3(&cone_apex[3 * i]));
        const double h = length(a - b);
        const double r0 = std::abs(double(cone_base_radius[i])), r1 = std::abs(double(cone_apex_radius[i]));
        if (!(h > 0)) bad("cylinder_apex[" + std::to_string(i) + "] coincides with cylinder_base");
        // A cone whose radii differ by more than 2^20 times its height has a
        // slope its quadratic cannot resolve in double (found by the API
        // fuzzer: height 1e-45, radii 0.3 and 0.1 "hit" 4 units away).
        if (std::abs(r1 - r0) > 0x1p20 * h)
            bad("cylinder_apex[" + std::to_string(i) + "] coincides with cylinder_base within " + format_number(h, 6) +
                ", too close for radii " + format_number(r0, 6) + " and " + format_number(r1, 6) +
                " (the radii may differ by at most 2^20 times the height)");
        cones_[i] = ConeData{b, (a - b) / h, h, r0, (r1 - r0) / h};
    }
    for (size_t i = 0; i < nm; ++i) validate_material(materials_[i], "materials[" + std::to_string(i) + "]");
    for (size_t i = 0; i < lights_.size(); ++i) prepare_light(lights_[i], "lights[" + std::to_string(i) + "]");
    if (!finite3(background_)) bad("background has a non-finite component");
    check_textures();
    check_generated();
    build_tangents();
    validate_camera(camera_);
    emitters_ = Emitters(tri_verts_, tri_mat_, materials_);

    compute_bounds(tri_bounds);
}

void Scene::compute_bounds(const Bounds& tri_bounds) {
    // Coordinates (and extents) within +-1e30 keep every box, distance and
    // grid cell computation finite in float.
    const size_t nt = num_triangles();
    bounds_ = Bounds();
    constexpr float kLimit = 1e30f;
    auto within = [&](const Bounds& b) {
        return std::max(std::abs(b.lo.x), std::max(std::abs(b.lo.y), std::abs(b.lo.z))) <= kLimit &&
               std::max(std::abs(b.hi.x), std::max(std::abs(b.hi.y), std::abs(b.hi.z))) <= kLimit;
    };
    // Triangles all within the limit (the common case) need no per-triangle pass.
    const size_t first = nt > 0 && within(tri_bounds) ? nt : 0;
    if (first) bounds_ = tri_bounds;
    for (size_t i = first; i < num_prims(); ++i) {
        const Bounds pb = prim_bounds(i);
        if (!within(pb)) {
            const char* what = kind_of(i) == PrimKind::Triangle ? "triangles"
                             : kind_of(i) == PrimKind::Sphere   ? "sphere_radii"
                                                                 : "cylinder_base_radius";
            bad(std::string(what) + "[" + std::to_string(local_index(i)) +
                "]: the primitive extends beyond +-1e30, which the core cannot represent");
        }
        bounds_.grow(pb);
    }
}

bool Scene::intersect_quadric(size_t prim, const RayPre& r, Hit& hit, float tmax) const {
    return intersect_quadric_inline(prim, r, hit, tmax);
}

Bounds Scene::prim_bounds(size_t prim) const {
    switch (kind_of(prim)) {
    case PrimKind::Triangle: return triangle_bounds(tri_verts_[3 * prim], tri_verts_[3 * prim + 1], tri_verts_[3 * prim + 2]);
    case PrimKind::Sphere: return sphere_bounds(centers_[local_index(prim)], radii_[local_index(prim)]);
    default: return cone_bounds(cones_[local_index(prim)]);
    }
}

Vec3 Scene::geometric_normal(const RayPre& r, const Hit& hit) const {
    const size_t prim = size_t(hit.prim);
    switch (kind_of(prim)) {
    case PrimKind::Triangle: return triangle_normal(tri_verts_[3 * prim], tri_verts_[3 * prim + 1], tri_verts_[3 * prim + 2]);
    case PrimKind::Sphere: return sphere_normal(r, hit.t, centers_[local_index(prim)]);
    default: return cone_normal(r, hit.t, cones_[local_index(prim)]);
    }
}

SurfacePoint Scene::surface(const RayPre& r, const Hit& hit) const {
    SurfacePoint sp;
    const size_t prim = size_t(hit.prim), k = local_index(prim);
    sp.ng = sp.ns = geometric_normal(r, hit);
    switch (kind_of(prim)) {
    case PrimKind::Triangle: {
        const Vec3* v = &tri_verts_[3 * prim];
        triangle_point(v[0], v[1], v[2], hit.u, hit.v, sp.p, sp.p_err);
        sp.material = tri_mat_[prim];
        if (!normals_.empty()) {
            const int32_t* f = &tris_[3 * prim];
            if (triangle_shading_normal(normal(f[0]), normal(f[1]), normal(f[2]), hit.u, hit.v, sp.ns) &&
                dot(sp.ns, sp.ng) < 0) {
                sp.ng = -sp.ng;   // the vertex normals define the outside
                sp.turned = true;
            }
        }
        break;
    }
    case PrimKind::Sphere:
        sphere_point(centers_[k], radii_[k], sp.ng, sp.p, sp.p_err);
        sp.material = sphere_mat_[k];
        break;
    default:
        cone_point(r, hit.t, cones_[k], sp.p, sp.p_err);
        sp.material = cone_mat_[k];
    }
    if (!finite3(sp.ng) || length(sp.ng) == 0) sp.ng = sp.ns = normalize(-r.ray.d);
    return sp;
}

size_t Scene::memory_bytes() const {
    return texture_bytes() + uvs_.size() * 4 + colors_.size() * 4 + generated_.size() * 4 + object_coords_.size() * 4 + object_normals_.size() * 4 + tangents_.size() * 4 + verts_.size() * 4 + tri_verts_.size() * 12 + normals_.size() * 4 + tris_.size() * 4 + tri_mat_.size() * 4 +
           centers_.size() * 12 + radii_.size() * 4 + sphere_mat_.size() * 4 + cones_.size() * sizeof(ConeData) +
           cone_mat_.size() * 4 + matte_class_.size() * 4 + class_keys_.size() * 4;
}

void Scene::set_matte_keys(std::vector<int32_t> keys, int layers) {
    if (layers < 1 || layers > kMaxMatteLayers)
        bad("matte_keys must have 1 to " + std::to_string(kMaxMatteLayers) + " keys per primitive, not " +
            std::to_string(layers));
    if (!keys.empty() && keys.size() != num_prims() * size_t(layers))
        bad("matte_keys must have one row per primitive (" + std::to_string(num_prims()) + ": triangles, spheres, "
            "then cylinders), not " + std::to_string(keys.size() / size_t(layers)));
    for (size_t i = 0; i < keys.size(); ++i)
        if (keys[i] < -1)
            bad("matte_keys[" + std::to_string(i / size_t(layers)) +
                (layers > 1 ? ", " + std::to_string(i % size_t(layers)) : std::string()) + "] is " +
                std::to_string(keys[i]) + ": a key is >= 0, or -1 for none");
    matte_layers_ = layers;
    matte_class_.assign(keys.empty() ? 0 : num_prims(), -1);
    class_keys_.clear();
    std::map<std::array<int32_t, kMaxMatteLayers>, int32_t> classes;
    for (size_t p = 0; p < matte_class_.size(); ++p) {
        std::array<int32_t, kMaxMatteLayers> row;
        row.fill(-1);
        std::copy(keys.begin() + ptrdiff_t(p * size_t(layers)), keys.begin() + ptrdiff_t((p + 1) * size_t(layers)),
                  row.begin());
        if (std::all_of(row.begin(), row.end(), [](int32_t k) { return k < 0; })) continue;
        const auto found = classes.emplace(row, int32_t(classes.size()));
        if (found.second) class_keys_.insert(class_keys_.end(), row.begin(), row.begin() + layers);
        matte_class_[p] = found.first->second;
    }
}

}  // namespace gw
