// The scene as the core sees it: flat arrays of triangles, spheres and cones,
// the material, light and camera records, the background and the world, and
// the textures with their images and the triangles' corner UVs and colours. Primitives share one global index space:
// [0, T) triangles, [T, T+S) spheres, [T+S, T+S+C) cones.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "buffer_pool.h"
#include "camera.h"
#include "cone.h"
#include "emitters.h"
#include "irradiance.h"
#include "lights.h"
#include "material.h"
#include "matte_coverage.h"
#include "ray.h"
#include "sphere.h"
#include "surface_point.h"
#include "texture_view.h"
#include "texture.h"
#include "triangle.h"
#include "world.h"
#include "world_shadows.h"

namespace gw {

// One instance moved to a new place: its vertices (and normals) recomputed
// from object space, as the exporter computes them (Scene::moved).
struct RigidMove {
    size_t vertex_start = 0;        // its first vertex in the scene's vertex array
    size_t triangle_start = 0;      // its triangles: [triangle_start, triangle_start + triangle_count)
    size_t triangle_count = 0;
    std::vector<float> positions;   // (k, 3) object space: the vertices [vertex_start, vertex_start + k)
    std::vector<float> normals;     // (k, 3) object space, or empty
    bool flat = false;              // unshared corners (3 per triangle) whose normals are the face normals
    double matrix[4][4] = {};       // object to world (rows as in Blender)
    bool has_previous = false;      // previous_matrix given: where the instance was in the scene moved from
    double previous_matrix[4][4] = {};
};

// How a scene was made from earlier ones by Scene::moved: for each of its
// latest ancestors (back to the last scene built from arrays, at most
// kMaxAncestors), the instances moved since, each one's triangles being the
// ancestor's under an affine map; so a grid of an ancestor serves this scene
// too, its rays mapped back (moved_grid.h). A viewport drag's requests cancel
// one another, so the grid at hand may be several versions old.
struct InstanceDelta {
    size_t triangle_start = 0, triangle_end = 0;
    double from_ancestor[3][4] = {};   // the ancestor's world space -> this scene's
};
struct SceneAncestor {
    uint64_t id = 0;                    // Scene::id() of the ancestor
    std::vector<InstanceDelta> moved;   // disjoint, by triangle_start
};
constexpr size_t kMaxAncestors = 16;

// Copies of one mesh, as the host declares them (Scene::set_instances):
// triangles [triangle_start, triangle_start + triangle_count) are mesh `mesh`
// placed by `matrix` (object to world, rows as in Blender), corner for corner
// the triangles of the mesh's first instance under matrix x (its matrix)^-1.
// The instanced grid (instanced_grid.h) traces such copies through one grid
// of the mesh, after checking that claim on their corners.
struct SceneInstance {
    size_t triangle_start = 0, triangle_count = 0;
    int32_t mesh = 0;
    double matrix[4][4] = {};
};
constexpr size_t kMaxMovedInstances = 8;   // an ancestor with more instances moved since is forgotten

class Scene {
public:
    // Arrays are copied into the scene (one memcpy each); the caller's buffers
    // may be freed afterwards. Every value is validated here, where it enters
    // the core: throws std::invalid_argument naming the array or record and
    // the first bad index.
    Scene(PooledVector<float> vertices, PooledVector<int32_t> triangles, PooledVector<float> normals,
          PooledVector<int32_t> tri_materials, std::vector<float> sphere_centers,
          std::vector<float> sphere_radii, std::vector<int32_t> sphere_materials,
          std::vector<float> cone_base, std::vector<float> cone_apex, std::vector<float> cone_base_radius,
          std::vector<float> cone_apex_radius, std::vector<int32_t> cone_materials,
          std::vector<Material> materials, std::vector<Light> lights, const CameraDesc& camera,
          Vec3 background, PooledVector<float> uvs = {}, PooledVector<float> colors = {},
          std::vector<std::shared_ptr<const Image>> images = {}, std::vector<Texture> textures = {},
          const World& world = World(), PooledVector<float> generated = {}, PooledVector<float> object_coords = {},
          PooledVector<float> object_normals = {});

    // A copy of this scene with the instances `moves` name moved: their
    // vertices become matrix x positions (in double, rounded to float), their
    // normals the inverse transpose of the matrix's linear part (its cofactor
    // matrix where it is singular) times normals, renormalised (flat
    // instances: their world-space face normals);
    // everything else is shared in value. Throws std::invalid_argument naming
    // the move when it does not fit the scene (ranges, shapes, a triangle
    // outside the move using its vertices, coordinates beyond +-1e30).
    std::shared_ptr<Scene> moved(const std::vector<RigidMove>& moves) const;

    // Declares the scene's instances (SceneInstance), before the scene is
    // shared. Throws std::invalid_argument naming the first bad one: a range
    // beyond the triangles or overlapping another, a non-finite matrix, a
    // negative mesh. A moved copy (moved()) keeps them: an instance a move
    // moves whole takes the move's matrix, one a move cuts into is dropped.
    void set_instances(std::vector<SceneInstance> instances);
    const std::vector<SceneInstance>& instances() const { return instances_; }
    // A scene of the primitives `prims` alone (ascending global indices),
    // moved by -shift (in double, rounded to float): its primitive i is
    // prims[i]. Geometry only (one default material; no lights, camera or
    // textures): what a structure over part of this scene is built over and
    // walks.
    std::shared_ptr<const Scene> part(const std::vector<uint32_t>& prims, const Vec3d& shift = Vec3d()) const;

    // The triangle arrays as they were given (or moved), for checks.
    struct Geometry {
        const PooledVector<float> *vertices, *normals;
        const PooledVector<int32_t> *triangles, *materials;
    };
    Geometry geometry() const { return {&verts_, &normals_, &tris_, &tri_mat_}; }
    // Unique among the scenes of this process (a moved copy gets its own).
    uint64_t id() const { return id_; }
    // Nearest first; empty for a scene built from arrays.
    const std::vector<SceneAncestor>& ancestors() const { return ancestors_; }

    // Forced inline: the AVX2 walk asks these for every primitive it tests,
    // and a call out of it costs (intersect_with says why).
    // (Counts kept as members: every primitive test asks which kind it has,
    // and tris_.size() / 3 cost a multiply and shifts each time.)
    __attribute__((always_inline)) size_t num_triangles() const { return nt_; }
    __attribute__((always_inline)) size_t num_spheres() const { return ns_; }
    __attribute__((always_inline)) size_t num_cones() const { return nc_; }
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

    // Per primitive (triangles, then spheres, then cones), `layers` keys (1 to
    // kMaxMatteLayers: say its object's, its material's) whose shares of each
    // pixel a render reports per layer (RenderSettings.matte_ranks: the host
    // turns them into Cryptomatte's mattes); -1: none. Row-major (primitive,
    // layer). Set once, before the scene is shared; empty: no keys.
    // Stored as each primitive's matte class (one per distinct row of keys;
    // -1 for a row of -1s), so that rays and samples count the few classes
    // they meet, however many triangles of one object they hit.
    void set_matte_keys(std::vector<int32_t> keys, int layers);
    int32_t matte_class(size_t prim) const { return matte_class_[prim]; }
    int32_t class_key(int32_t cls, int layer) const { return class_keys_[size_t(cls) * size_t(matte_layers_) + size_t(layer)]; }
    bool has_matte_keys() const { return !matte_class_.empty(); }
    int matte_layers() const { return matte_layers_; }

    Bounds prim_bounds(size_t prim) const;
    const Vec3& sphere_center(size_t s) const { return centers_[s]; }
    float sphere_radius(size_t s) const { return radii_[s]; }
    const Bounds& bounds() const { return bounds_; }

    // Tests one primitive; on a hit nearer than hit.t, updates hit and returns true.
    // Triangles are tested inline (the hot path); quadrics out of line.
    inline bool intersect(size_t prim, const RayPre& r, Hit& hit) const;
    bool intersect_quadric(size_t prim, const RayPre& r, Hit& hit, float tmax) const;
    // The same two, for code compiled for another instruction set (the AVX2
    // walk): intersect_with takes the quadric test as `quadric(prim, r, hit,
    // tmax)`, and intersect_quadric_inline is that test's body, inlined where
    // it is called. A walk wraps it in a function of its own instruction set,
    // so that no call leaves that set: calls from AVX code into code compiled
    // for plain x86-64 cost the AVX2 walk a factor 2-3 on an Intel Xeon.
    template <class QuadricTest>
    inline bool intersect_with(size_t prim, const RayPre& r, Hit& hit, const QuadricTest& quadric) const;
    inline bool intersect_quadric_inline(size_t prim, const RayPre& r, Hit& hit, float tmax) const;
    SurfacePoint surface(const RayPre& r, const Hit& hit) const;
    Vec3 geometric_normal(const RayPre& r, const Hit& hit) const;

    // The triangles' corners, 3 per triangle, in triangle order (9 contiguous floats each).
    const Vec3* triangle_vertices() const { return tri_verts_.data(); }
    const std::vector<Material>& materials() const { return materials_; }
    const std::vector<Light>& lights() const { return lights_; }
    const CameraDesc& camera() const { return camera_; }
    Vec3 background() const { return background_; }
    const World& world() const { return world_; }
    // What a ray that misses everything sees: the environment texture, else the background.
    // (World.inset, where set and d falls in its square, instead of the environment)
    Vec3 miss(const Vec3& d) const {
        if (world_.environment < 0) return background_;
        const Vec3 e = to_environment(d);
        float u, v;
        int32_t texture = world_.environment;
        const Vec3 l = world_.inset >= 0 ? rotate(world_.inset_frame, e) : Vec3();
        if (l.z > 0 && std::abs(l.x) < world_.inset_extent * l.z && std::abs(l.y) < world_.inset_extent * l.z) {
            u = 0.5f + 0.5f * l.x / (l.z * world_.inset_extent);
            v = 0.5f + 0.5f * l.y / (l.z * world_.inset_extent);
            texture = world_.inset;
        } else {
            equirect_uv(e, u, v);
        }
        const Texture& t = textures_[size_t(texture)];
        return sample_image(*images_[size_t(t.image)], t, u, v).rgb * world_.environment_strength;
    }
    // The ambient light a diffuse surface facing n gets (times its colour and
    // kd): World.ambient plus the environment's irradiance / pi where
    // World.environment_light is set.
    Vec3 ambient(const Vec3& n) const {
        if (!env_light_) return world_.ambient;
        const Vec3 e = to_environment(n);
        return world_.ambient + env_irradiance_.at(e) + (sun_irradiance_.empty() ? Vec3() : sun_irradiance_.at(e));
    }
    // The part of ambient(n) that the environment's bright cells (a sun) give,
    // and those cells as a map to sample (empty without a sun).
    Vec3 sun_ambient(const Vec3& n) const {
        return env_light_ && !sun_irradiance_.empty() ? sun_irradiance_.at(to_environment(n)) : Vec3();
    }
    const WorldMap& sun_map() const { return sun_map_; }
    // A world direction in the environment image's frame (World.environment_rotation), and back.
    Vec3 to_environment(const Vec3& d) const { return env_rotated_ ? rotate(world_.environment_rotation, d) : d; }
    Vec3 from_environment(const Vec3& d) const {
        return env_rotated_ ? rotate_back(world_.environment_rotation, d) : d;
    }
    // The environment's luminance map, without its sun, for drawing world shadow
    // rays (empty without environment light).
    const WorldMap& world_map() const { return world_map_; }
    // The world's radiance along d where it lights surfaces: the ambient colour,
    // plus the environment where World.environment_light is set (its radiance
    // map's, which the irradiance table integrates).
    Vec3 world_light(const Vec3& d) const {
        return env_light_ ? world_.ambient + world_map_.radiance(to_environment(d)) : world_.ambient;
    }
    bool has_ambient() const {
        return env_light_ || world_.ambient.x != 0 || world_.ambient.y != 0 || world_.ambient.z != 0;
    }
    // The emissive triangles that light the scene (materials with emits_light).
    const Emitters& emitters() const { return emitters_; }
    int32_t triangle_material(int32_t tri) const { return tri_mat_[size_t(tri)]; }
    // Whether some material lets light through: shadow rays then look at what they hit.
    bool transparent_shadows() const { return transparent_shadows_; }
    // Whether a material is hidden from some kind of ray (Material::seen_by).
    bool hides_from_rays() const { return hides_from_rays_; }
    // The material at a hit with its textures and colour attribute applied
    // (call only when materials()[sp.material].varies()); view: the ray's side
    // of the hit, for textures at Normal, Camera, Window or Reflection coordinates.
    Material shade(const Material& m, const Hit& hit, const TextureView& view) const;
    // The shading normal at a hit with the material's normal map, then its
    // bump map applied (sp.ns where it has none, or the triangle has no UVs or
    // no UV area). view.wi: the unit direction back along the ray (a normal map's
    // normal is kept from reflecting it into the surface, as Cycles keeps it).
    Vec3 mapped_normal(const Material& m, const Hit& hit, const SurfacePoint& sp, const TextureView& view) const;
    // The material's alpha at a hit (its alpha texture applied).
    float alpha_at(const Material& m, const Hit& hit, const TextureView& view) const;
    size_t memory_bytes() const;
    size_t texture_bytes() const;   // the images, each counted once

private:
    Vec3 vert(int32_t i) const {
        const size_t k = 3 * size_t(i);
        return {verts_[k], verts_[k + 1], verts_[k + 2]};
    }
    Vec3 normal(int32_t i) const {
        const size_t k = 3 * size_t(i);
        return {normals_[k], normals_[k + 1], normals_[k + 2]};
    }

    // The arrays that grow with the mesh are pooled (buffer_pool.h): a viewport's
    // next scene version reuses them.
    PooledVector<float> verts_, normals_;
    PooledVector<Vec3> tri_verts_;   // 3 per triangle: the hot loop reads one contiguous record
    PooledVector<int32_t> tris_, tri_mat_;
    size_t nt_ = 0, ns_ = 0, nc_ = 0;   // triangles, spheres, cones (set once, by the constructor)
    std::vector<Vec3> centers_;
    std::vector<float> radii_;
    std::vector<int32_t> sphere_mat_;
    std::vector<ConeData> cones_;
    std::vector<int32_t> cone_mat_;
    std::vector<Material> materials_;
    std::vector<Light> lights_;
    CameraDesc camera_;
    Vec3 background_;
    PooledVector<float> uvs_, colors_;   // 6 / 9 floats per triangle (corner UVs / RGB), or empty
    // 9 floats per triangle (corner Generated / Object coordinates), or empty
    PooledVector<float> generated_, object_coords_, object_normals_;
    // 12 floats per triangle (tangents.h) where a material has a normal map
    // and the triangles have UVs, else empty.
    std::vector<float> tangents_;
    std::vector<int32_t> matte_class_, class_keys_;   // set_matte_keys
    int matte_layers_ = 1;
    void build_tangents();
    // Those of triangles [first, first + count) again (an instance moved: it
    // shares no vertex with the rest).
    void update_tangents(size_t first, size_t count);
    std::vector<std::shared_ptr<const Image>> images_;
    std::vector<Texture> textures_;
    World world_;
    Emitters emitters_;
    bool env_light_ = false;          // world_.environment_light with an environment
    bool env_rotated_ = false;        // world_.environment_rotation is not the identity
    Irradiance env_irradiance_, sun_irradiance_;   // the environment without its bright cells, and those
    WorldMap world_map_, sun_map_;
    bool transparent_shadows_ = false;
    bool hides_from_rays_ = false;
    Bounds bounds_;
    uint64_t id_ = next_id();
    std::vector<SceneAncestor> ancestors_;
    std::vector<SceneInstance> instances_;   // set_instances
    struct PartTag {};
    explicit Scene(PartTag) {}   // part()
    static uint64_t next_id();

    // The texture at a hit whose UV map gives (u, v) (hit_uv).
    Rgba lookup(int32_t texture, const Hit& hit, float u, float v, const TextureView& view) const {
        const Texture& t = textures_[size_t(texture)];
        if (!plain_image(t)) return lookup_vector(t, hit, u, v, view);
        if (uv_mapped(t)) map_uv(t, u, v);
        const int32_t k = texture_image(t, u, v);
        return k < 0 ? missing_texel() : sample_image(*images_[size_t(k)], t, u, v);
    }
    // A procedural texture, or an image at other coordinates or mapped in 3D (see Texture).
    Rgba lookup_vector(const Texture& t, const Hit& hit, float u, float v, const TextureView& view) const;
    // The texture's point at the hit, before vector_transform: (u, v, 0) of its UV map, or
    // its coordinates there (hit_point, or those view gives).
    Vec3 texture_point(const Texture& t, const Hit& hit, float u, float v, const TextureView& view) const;
    // Such a texture at the point p of its coordinates, after vector_transform.
    Rgba pattern_at(const Texture& t, const Vec3& p) const;
    // An image texture at (x, y), mapped on by uv_transform.
    Rgba image_at(const Texture& t, float x, float y) const;
    // A box-projected image (Texture::projection) at the point p, for the object-space normal n.
    Rgba box_projected(const Texture& t, const Vec3& p, const Vec3& n) const;
    // The texture point (before vector_transform) of each corner of triangle prim
    // for t's coordinates; false where the scene has no such array, and for
    // coordinates that do not move with the point along the triangle as an
    // affine map of it (the normals, Reflection and Incoming: Cycles' bump takes
    // them as fixed, so they bend nothing; Window: a perspective division), and
    // for a box-projected image (its blend turns with the normal: not bumped).
    bool corner_points(const Texture& t, size_t prim, const TextureView& view, Vec3 c[3]) const;
    // The bump map's slopes on triangle prim at the hit: the height's change per
    // unit of the triangle's parameters (hu, hv) along which the surface moves by
    // T and B. An image at the UV map: per unit of u and v, from its texels; any
    // other texture: per unit of the barycentrics of corners 1 and 2, from central
    // differences of the pattern. False where there are none (no UVs, UVs or
    // corners of no area).
    bool image_slopes(const Texture& t, const Hit& hit, Vec3& T, Vec3& B, float& hu, float& hv) const;
    bool pattern_slopes(const Texture& t, const Hit& hit, const TextureView& view, Vec3& T, Vec3& B, float& hu,
                        float& hv) const;
    // The hit's point in the per-corner array of those coordinates (Generated, Object or
    // Normal: that one normalised, on view's side) or in world space (Position).
    Vec3 hit_point(const Hit& hit, TextureCoords coords, bool backfacing = false) const;
    // The per-corner array of Generated, Object or Normal coordinates.
    const PooledVector<float>& corner_array(TextureCoords coords) const;
    void hit_uv(const Hit& hit, float& u, float& v) const;
    // The hit's corner colours (Scene(colors=...)) interpolated; 0 where it has none.
    Vec3 corner_colour(const Hit& hit) const;
    // sp.ns with the material's normal map applied (sp.ns where it has none),
    // kept from reflecting wo into the surface, as Cycles' Normal Map node
    // keeps it (its Bump node does not).
    Vec3 normal_mapped(const Material& m, const Hit& hit, const SurfacePoint& sp, const TextureView& view) const;
    // n bent by the material's bump map (Blender's Bump node): normalize(n -
    // bump_distance x the height's gradient along the surface, its part along
    // n removed along the geometric normal), blended with n by bump_strength
    // (n where it has none).
    Vec3 bumped(const Material& m, const Hit& hit, const Vec3& n, const TextureView& view) const;
    void check_textures();   // scene_textures.cpp
    void check_generated() const;
    void compute_bounds(const Bounds& tri_bounds);   // bounds_ (and the +-1e30 check), given the triangles'
    void apply(const RigidMove& m, size_t index);     // scene_moved.cpp
    std::vector<SceneAncestor> ancestors_after(const std::vector<RigidMove>& moves) const;
    bool where_it_was(const RigidMove& m) const;
    std::vector<SceneInstance> instances_after(const std::vector<RigidMove>& moves) const;   // scene_moved.cpp
};

// A hit at exactly the current hit's t wins when its primitive index is
// lower: with the hit decided on t alone (triangle.h), the nearest hit is the
// same whatever order the primitives are tested in (brute force, the uniform
// grid's cells, the adaptive grid's SIMD lanes).
template <class QuadricTest>
__attribute__((always_inline)) inline bool Scene::intersect_with(size_t prim, const RayPre& r, Hit& hit,
                                                                 const QuadricTest& quadric) const {
    const float tmax = int32_t(prim) < hit.prim ? next_up(hit.t) : hit.t;   // t < next_up(x) <=> t <= x
    if (prim >= num_triangles()) {
        if (__builtin_expect(r.ray.after < 0, 1)) return quadric(prim, r, hit, tmax);
        Hit found = hit;   // (a resumed ray: see below)
        if (!quadric(prim, r, found, tmax) || (int32_t(prim) <= r.ray.after && found.t == next_up(r.ray.tmin)))
            return false;
        hit = found;
        return true;
    }
    float t, u, v;
    if (!intersect_triangle(r, &tri_verts_[3 * prim].x, tmax, t, u, v)) return false;
    // (a resumed ray, Ray::after: of the hits at the t passed, only a later primitive's counts)
    if (__builtin_expect(int32_t(prim) <= r.ray.after, 0) && t == next_up(r.ray.tmin)) return false;
    hit.t = t;
    hit.prim = int32_t(prim);
    hit.u = u;
    hit.v = v;
    return true;
}

__attribute__((always_inline)) inline bool Scene::intersect(size_t prim, const RayPre& r, Hit& hit) const {
    return intersect_with(prim, r, hit, [this](size_t p, const RayPre& ray, Hit& h, float tmax) {
        return intersect_quadric(p, ray, h, tmax);
    });
}

__attribute__((always_inline)) inline bool Scene::intersect_quadric_inline(size_t prim, const RayPre& r, Hit& hit,
                                                                           float tmax) const {
    float t;
    const size_t s = prim - num_triangles();
    if (s < num_spheres()) {
        if (!intersect_sphere(r, centers_[s], radii_[s], tmax, t)) return false;
    } else if (!intersect_cone(r, cones_[s - num_spheres()], tmax, t)) {
        return false;
    }
    hit.t = t;
    hit.prim = int32_t(prim);
    hit.u = hit.v = 0;
    return true;
}

}  // namespace gw
