// The scene's textures: checking them where they enter, the texture
// coordinates of a hit, and materials evaluated at a hit. See scene.h.
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "noise.h"
#include "procedural.h"
#include "voronoi.h"
#include "scene.h"
#include "tangents.h"

namespace gw {
namespace {

[[noreturn]] void bad(const std::string& msg) { throw std::invalid_argument(msg); }

float clamp01(float x) { return x > 0 ? (x < 1 ? x : 1) : 0; }   // NaN -> 0

// The Principled -> Whitted mapping of a roughness r (blender_addon/export/materials.py).
float shininess_of(float r) {
    const float a = std::max(r * r, 1e-3f);
    return std::min(2.0f / (a * a) - 2.0f, 1000.0f);
}

}  // namespace

void Scene::check_textures() {
    const size_t nt = num_triangles();
    if (!uvs_.empty() && uvs_.size() != 6 * nt)
        bad("uvs must have shape (M, 3, 2): one (u, v) per triangle corner, got " + std::to_string(uvs_.size()) +
            " values for " + std::to_string(nt) + " triangles");
    if (!colors_.empty() && colors_.size() != 9 * nt)
        bad("colors must have shape (M, 3, 3): one RGB per triangle corner, got " + std::to_string(colors_.size()) +
            " values for " + std::to_string(nt) + " triangles");
    for (size_t i = 0; i < uvs_.size(); ++i)
        if (!std::isfinite(uvs_[i])) bad("uvs[" + std::to_string(i / 6) + "] has a non-finite value");
    for (size_t i = 0; i < colors_.size(); ++i)
        if (!std::isfinite(colors_[i])) bad("colors[" + std::to_string(i / 9) + "] has a non-finite value");
    for (const auto& [values, name] : {std::pair{&generated_, "generated"}, std::pair{&object_coords_, "object_coords"},
                                       std::pair{&object_normals_, "object_normals"}}) {
        if (!values->empty() && values->size() != 9 * nt)
            bad(std::string(name) + " must have shape (M, 3, 3): one point per triangle corner, got " +
                std::to_string(values->size()) + " values for " + std::to_string(nt) + " triangles");
        for (size_t i = 0; i < values->size(); ++i)
            if (!std::isfinite((*values)[i]))
                bad(std::string(name) + "[" + std::to_string(i / 9) + "] has a non-finite value");
    }
    for (size_t i = 0; i < images_.size(); ++i)
        if (!images_[i]) bad("images[" + std::to_string(i) + "] is missing");
    for (size_t i = 0; i < textures_.size(); ++i) {
        const std::string where = "textures[" + std::to_string(i) + "]";
        validate_texture(textures_[i], where);
        const int32_t k = textures_[i].image;
        if (textures_[i].kind != TextureKind::Image) continue;   // (validate_texture: image -1)
        if (k < 0 || size_t(k) >= images_.size())
            bad(where + ".image = " + std::to_string(k) + " is out of range: images has " +
                std::to_string(images_.size()) + " entries");
        const auto& tiles = textures_[i].tiles;
        for (size_t j = 1; j < tiles.size(); j += 2)
            if (tiles[j] < 0 || size_t(tiles[j]) >= images_.size())
                bad(where + ".tiles: tile " + std::to_string(tiles[j - 1]) + "'s image " + std::to_string(tiles[j]) +
                    " is out of range: images has " + std::to_string(images_.size()) + " entries");
    }
    auto check_index = [&](int32_t k, const std::string& where) {
        if (k >= int32_t(textures_.size()))
            bad(where + " = " + std::to_string(k) + " is out of range: textures has " +
                std::to_string(textures_.size()) + " entries");
    };
    for (size_t i = 0; i < materials_.size(); ++i) {
        const Material& m = materials_[i];
        const std::string where = "materials[" + std::to_string(i) + "].";
        check_index(m.color_texture, where + "color_texture");
        check_index(m.roughness_texture, where + "roughness_texture");
        check_index(m.metallic_texture, where + "metallic_texture");
        check_index(m.alpha_texture, where + "alpha_texture");
        check_index(m.normal_texture, where + "normal_texture");
        check_index(m.emission_texture, where + "emission_texture");
        check_index(m.bump_texture, where + "bump_texture");
        // A normal map is an image's colours in the frame of its own (u, v).
        // (A bump map takes any texture's slopes: Scene::bumped.)
        if (m.normal_texture >= 0 && !plain_image(textures_[size_t(m.normal_texture)]))
            bad(where + "normal_texture = " + std::to_string(m.normal_texture) +
                " names a procedural texture or one at other coordinates than the UV map: "
                "a normal map takes an image at the UV map");
        transparent_shadows_ = transparent_shadows_ || m.lets_light_through();
        hides_from_rays_ = hides_from_rays_ || !m.visible_camera || !m.visible_glossy || !m.visible_transmission;
    }
    validate_world(world_);
    for (const auto& [index, name] : {std::pair{world_.environment, "World.environment"}, std::pair{world_.inset, "World.inset"}}) {
        check_index(index, name);
        if (index < 0) continue;
        const Texture& t = textures_[size_t(index)];
        if (!plain_image(t))
            bad(std::string(name) + " = " + std::to_string(index) +
                " names a procedural texture or one with coordinates or a vector_transform: an environment is an image "
                "looked up along the ray's direction");
        if (!t.tiles.empty())
            bad(std::string(name) + " = " + std::to_string(index) +
                " names a texture of UDIM tiles: an environment is one image");
        if (uv_mapped(t))
            bad(std::string(name) + " = " + std::to_string(index) +
                " names a texture with a uv_transform, which an environment does not use: "
                "turn it with World.environment_rotation");
        if (adjusts(t))
            bad(std::string(name) + " = " + std::to_string(index) +
                " names a texture with a channel, gain, bias or clamp, which an environment does not use: "
                "scale it with World.environment_strength");
    }
    env_light_ = world_.environment_light && world_.environment >= 0;
    env_rotated_ = world_.environment_rotation != std::array<float, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (env_light_) {
        const Texture& t = textures_[size_t(world_.environment)];
        // Every texel read once into 512 x 256 cells: the world shadows' map, and the
        // irradiance table's 128 x 64 source.
        // A sun's cells are split off: world shadows sample them as a light.
        RadianceMap fine = radiance_map(*images_[size_t(t.image)], t, world_.environment_strength, 512), sun;
        if (split_bright(fine, sun)) {
            sun_irradiance_ = Irradiance(coarser(sun, 128));
            sun_map_ = WorldMap(sun);
        }
        env_irradiance_ = Irradiance(coarser(fine, 128));
        world_map_ = WorldMap(fine);
    }
}

// Generated, Object, Normal and Position coordinates exist on triangles only
// (Scene(generated=...), Scene(object_coords=...), Scene(object_normals=...);
// a triangle's world corners): a material whose textures take them may not be
// on a sphere or a cone, and triangles using the first three need the array.
// (Camera, Window and Reflection coordinates come from the hit's point and
// normal and the ray: any primitive has them.)
namespace {

// Per material, whether one of its textures (colour, roughness, metallic, alpha,
// emission, bump) is one that `reads` says yes to.
template <class Reads>
std::vector<uint8_t> materials_reading(const std::vector<Material>& materials, Reads reads) {
    std::vector<uint8_t> out(materials.size(), 0);
    for (size_t i = 0; i < materials.size(); ++i) {
        const Material& m = materials[i];
        out[i] = reads(m.color_texture) || reads(m.roughness_texture) || reads(m.metallic_texture) ||
                 reads(m.alpha_texture) || reads(m.emission_texture) || reads(m.bump_texture);
    }
    return out;
}

bool any_reads(const std::vector<uint8_t>& reads) { return std::find(reads.begin(), reads.end(), uint8_t(1)) != reads.end(); }

}  // namespace

void Scene::check_generated() const {
    for (const TextureCoords coords :
         {TextureCoords::Generated, TextureCoords::Object, TextureCoords::Normal, TextureCoords::Position}) {
        // (a box-projected image reads the object-space normals, whatever its coordinates)
        auto reads = [&](int32_t k) {
            if (k < 0) return false;
            const Texture& t = textures_[size_t(k)];
            return t.coordinates == coords || (coords == TextureCoords::Normal && t.kind == TextureKind::Image &&
                                               t.projection == ImageProjection::Box);
        };
        const std::vector<uint8_t> uses = materials_reading(materials_, reads);
        if (!any_reads(uses)) continue;   // (no pass over the primitives)
        const std::string kind = enum_id(coords);
        auto what = [&](int32_t mat) {
            return "materials[" + std::to_string(mat) + "] has a texture at " + kind + " coordinates, ";
        };
        for (size_t i = 0; i < sphere_mat_.size(); ++i)
            if (uses[size_t(sphere_mat_[i])])
                bad(what(sphere_mat_[i]) + "which spheres do not have: sphere_materials[" + std::to_string(i) +
                    "] uses it");
        for (size_t i = 0; i < cone_mat_.size(); ++i)
            if (uses[size_t(cone_mat_[i])])
                bad(what(cone_mat_[i]) + "which cylinders do not have: cylinder_materials[" + std::to_string(i) +
                    "] uses it");
        if (coords == TextureCoords::Position) continue;   // (the triangles' own corners)
        const bool given = !corner_array(coords).empty();
        const std::string array = coords == TextureCoords::Generated ? "generated"
                                  : coords == TextureCoords::Object  ? "object_coords"
                                                                     : "object_normals";
        if (!given)
            for (size_t i = 0; i < tri_mat_.size(); ++i)
                if (uses[size_t(tri_mat_[i])])
                    bad(what(tri_mat_[i]) + "and triangle_materials[" + std::to_string(i) +
                        "] uses it, but the scene has none (Scene(" + array + "=...))");
    }
    // An attribute texture reads the triangles' corner colours (spheres and cones read none: black).
    if (!colors_.empty()) return;
    const std::vector<uint8_t> reads = materials_reading(
        materials_, [&](int32_t k) { return k >= 0 && textures_[size_t(k)].kind == TextureKind::Attribute; });
    if (!any_reads(reads)) return;   // (no pass over the triangles)
    for (size_t i = 0; i < tri_mat_.size(); ++i) {
        if (reads[size_t(tri_mat_[i])])
            bad("materials[" + std::to_string(tri_mat_[i]) + "] has an attribute texture, and triangle_materials[" +
                std::to_string(i) + "] uses it, but the scene has no corner colours (Scene(colors=...))");
    }
}

const PooledVector<float>& Scene::corner_array(TextureCoords coords) const {
    return coords == TextureCoords::Generated ? generated_ : coords == TextureCoords::Object ? object_coords_ : object_normals_;
}

Vec3 Scene::hit_point(const Hit& hit, TextureCoords coords, bool backfacing) const {
    if (coords == TextureCoords::Position) {
        if (size_t(hit.prim) >= num_triangles()) return Vec3(0, 0, 0);   // (check_generated)
        const Vec3* c = &tri_verts_[3 * size_t(hit.prim)];
        return c[0] * (1.0f - hit.u - hit.v) + c[1] * hit.u + c[2] * hit.v;
    }
    const PooledVector<float>& values = corner_array(coords);
    if (values.empty() || size_t(hit.prim) >= num_triangles()) return Vec3(0, 0, 0);   // (check_generated)
    const float* c = &values[9 * size_t(hit.prim)];
    const float b0 = 1.0f - hit.u - hit.v;
    const Vec3 p = Vec3(c[0], c[1], c[2]) * b0 + Vec3(c[3], c[4], c[5]) * hit.u + Vec3(c[6], c[7], c[8]) * hit.v;
    if (coords != TextureCoords::Normal) return p;
    // (Cycles: the world normal under the transpose of the object's matrix, normalised,
    // which is the object's own normal, interpolated and normalised)
    const float len = length(p);
    if (!(len > 0) || !std::isfinite(len)) return Vec3(0, 0, 0);
    return p * ((backfacing ? -1.0f : 1.0f) / len);
}

Vec3 Scene::texture_point(const Texture& t, const Hit& hit, float u, float v, const TextureView& view) const {
    if (t.kind == TextureKind::Attribute) return corner_colour(hit);   // (its "point" is the attribute's value)
    switch (t.coordinates) {
    case TextureCoords::UV: return Vec3(u, v, 0);
    case TextureCoords::Camera: return view.camera ? view.camera->camera_point(view.p) : Vec3(0, 0, 0);
    case TextureCoords::Window: return view.camera ? view.camera->window_point(view.p) : Vec3(0, 0, 0);
    case TextureCoords::Reflection: return view.reflection();
    case TextureCoords::GeometryNormal: return view.n;
    case TextureCoords::TrueNormal: return view.ng;
    case TextureCoords::Incoming: return view.wi;
    default: return hit_point(hit, t.coordinates, view.backfacing);
    }
}

Rgba Scene::lookup_vector(const Texture& t, const Hit& hit, float u, float v, const TextureView& view) const {
    Vec3 p = texture_point(t, hit, u, v, view);
    if (vector_mapped(t)) p = map_vector(t, p);
    if (t.kind == TextureKind::Image && t.projection == ImageProjection::Box)
        return box_projected(t, p, hit_point(hit, TextureCoords::Normal, view.backfacing));
    return pattern_at(t, p);
}

namespace {

// Cycles' weights of a box projection's three lookups (along x, y and z) for the
// object-space normal n: one axis alone where n leans to it by more than the
// blend's limit, two or three blended between.
Vec3 box_weights(Vec3 n, float blend) {
    n = Vec3(std::abs(n.x), std::abs(n.y), std::abs(n.z));
    const float sum = n.x + n.y + n.z;
    if (!(sum > 0) || !std::isfinite(sum)) return Vec3(1, 0, 0);
    n = n * (1.0f / sum);
    const float limit = 0.5f * (1.0f + blend);
    auto sat = [](float x) { return std::min(std::max(x, 0.0f), 1.0f); };
    if (n.x > limit * (n.x + n.y) && n.x > limit * (n.x + n.z)) return Vec3(1, 0, 0);
    if (n.y > limit * (n.x + n.y) && n.y > limit * (n.y + n.z)) return Vec3(0, 1, 0);
    if (n.z > limit * (n.x + n.z) && n.z > limit * (n.y + n.z)) return Vec3(0, 0, 1);
    if (!(blend > 0)) return Vec3(1, 0, 0);
    if (n.z < (1 - limit) * (n.y + n.x)) {
        const float wx = sat((n.x / (n.x + n.y) - 0.5f * (1 - blend)) / blend);
        return Vec3(wx, 1 - wx, 0);
    }
    if (n.x < (1 - limit) * (n.y + n.z)) {
        const float wy = sat((n.y / (n.y + n.z) - 0.5f * (1 - blend)) / blend);
        return Vec3(0, wy, 1 - wy);
    }
    if (n.y < (1 - limit) * (n.x + n.z)) {
        const float wx = sat((n.x / (n.x + n.z) - 0.5f * (1 - blend)) / blend);
        return Vec3(wx, 0, 1 - wx);
    }
    const float d = 2 * limit - 1;
    return Vec3(((2 - limit) * n.x + (limit - 1)) / d, ((2 - limit) * n.y + (limit - 1)) / d,
                ((2 - limit) * n.z + (limit - 1)) / d);
}

}  // namespace

Rgba Scene::box_projected(const Texture& t, const Vec3& p, const Vec3& n) const {
    const Vec3 w = box_weights(n, std::min(std::max(t.projection_blend, 0.0f), 1.0f));
    Rgba out{Vec3(), 0};
    // (each face's image the right way round, as Cycles turns them)
    const float uv[3][2] = {{n.x < 0 ? 1 - p.y : p.y, p.z}, {n.y > 0 ? 1 - p.x : p.x, p.z}, {n.z > 0 ? 1 - p.y : p.y, p.x}};
    const float weights[3] = {w.x, w.y, w.z};
    for (int a = 0; a < 3; ++a) {
        if (!(weights[a] > 0)) continue;
        const Rgba f = image_at(t, uv[a][0], uv[a][1]);
        out.rgb = out.rgb + f.rgb * weights[a];
        out.a += f.a * weights[a];
    }
    return out;
}

Rgba Scene::image_at(const Texture& t, float x, float y) const {
    if (uv_mapped(t)) map_uv(t, x, y);
    const int32_t k = texture_image(t, x, y);
    return k < 0 ? missing_texel() : sample_image(*images_[size_t(k)], t, x, y);
}

Rgba Scene::pattern_at(const Texture& t, const Vec3& p) const {
    if (t.kind == TextureKind::Checker) return checker_color(t, p);
    if (t.kind == TextureKind::Gradient) return gradient_color(t, p);
    if (t.kind == TextureKind::Noise) return noise_color(t, p);
    if (t.kind == TextureKind::Voronoi) return voronoi_color(t, p);
    if (t.kind == TextureKind::Wave) return wave_color(t, p);
    if (t.kind == TextureKind::Magic) return magic_color(t, p);
    if (t.kind == TextureKind::WhiteNoise) return white_noise_color(t, p);
    if (t.kind == TextureKind::Brick) return brick_color(t, p);
    if (t.kind == TextureKind::Attribute) return Rgba{p, (p.x + p.y + p.z) * (1.0f / 3.0f)};   // (Fac: the mean)
    if (t.projection == ImageProjection::Sphere || t.projection == ImageProjection::Tube) {
        // (Cycles: the point moved from the unit box to [-1, 1]^3, then its angles)
        const Vec3 q = (p - Vec3(0.5f, 0.5f, 0.5f)) * 2.0f;
        float x = 0, y = 0;
        if (t.projection == ImageProjection::Sphere) {
            const float l2 = dot(q, q);
            if (l2 > 0) {
                x = q.x == 0 && q.y == 0 ? 0.0f : 0.5f - std::atan2(q.x, q.y) * float(0.5 / kPi);
                y = 1.0f - std::acos(std::min(std::max(q.z / std::sqrt(l2), -1.0f), 1.0f)) * float(1 / kPi);
            }
        } else {
            const float len = std::sqrt(q.x * q.x + q.y * q.y);
            if (len > 0) {
                x = (1.0f - std::atan2(q.x / len, q.y / len) * float(1 / kPi)) * 0.5f;
                y = (q.z + 1.0f) * 0.5f;
            }
        }
        return image_at(t, x, y);
    }
    return image_at(t, p.x, p.y);
}

Vec3 Scene::corner_colour(const Hit& hit) const {
    if (colors_.empty() || size_t(hit.prim) >= num_triangles()) return Vec3(0, 0, 0);   // (check_attributes)
    const float* c = &colors_[9 * size_t(hit.prim)];
    const float b0 = 1.0f - hit.u - hit.v;
    return Vec3(c[0], c[1], c[2]) * b0 + Vec3(c[3], c[4], c[5]) * hit.u + Vec3(c[6], c[7], c[8]) * hit.v;
}

void Scene::hit_uv(const Hit& hit, float& u, float& v) const {
    u = v = 0;
    if (uvs_.empty() || size_t(hit.prim) >= num_triangles()) return;
    const float* t = &uvs_[6 * size_t(hit.prim)];
    const float b0 = 1.0f - hit.u - hit.v;
    u = b0 * t[0] + hit.u * t[2] + hit.v * t[4];
    v = b0 * t[1] + hit.u * t[3] + hit.v * t[5];
}

Material Scene::shade(const Material& m, const Hit& hit, const TextureView& view) const {
    Material out = m;
    float u, v;
    hit_uv(hit, u, v);
    if (m.color_texture >= 0)
        out.color = color_of(textures_[size_t(m.color_texture)], lookup(m.color_texture, hit, u, v, view));
    if (m.vertex_color && !colors_.empty() && size_t(hit.prim) < num_triangles()) {
        const Vec3 corner = corner_colour(hit);
        // (with a colour texture: their product, a Mix node multiplying the image by the attribute)
        out.color = m.color_texture >= 0 ? out.color * corner : corner;
    }
    if (m.roughness_texture >= 0) {
        const float r = clamp01(scalar_of(textures_[size_t(m.roughness_texture)], lookup(m.roughness_texture, hit, u, v, view)));
        out.shininess = shininess_of(r);
        out.ks = m.ks * (out.shininess + 8.0f) / (m.shininess + 8.0f);   // same specular weight, new lobe
        out.roughness = r;
    }
    if (m.metallic_texture >= 0) {
        // The record holds the non-metal (metallic = 0) mapping; blend towards the metal.
        const float mt = clamp01(scalar_of(textures_[size_t(m.metallic_texture)], lookup(m.metallic_texture, hit, u, v, view)));
        const float norm = (out.shininess + 8.0f) / 8.0f, f0 = out.ks / norm;
        out.kd = m.kd * (1 - mt);
        out.transmittance = m.transmittance * (1 - mt);
        out.mirror = mt;
        out.metallic = mt;
        out.ks = ((1 - mt) * f0 + mt) * norm;
    }
    if (m.alpha_texture >= 0) out.alpha = alpha_at(m, hit, view);
    if (m.emission_texture >= 0) {
        out.emission_color =
            color_of(textures_[size_t(m.emission_texture)], lookup(m.emission_texture, hit, u, v, view)) * m.emission_color;
    }
    return out;
}

void Scene::build_tangents() {
    tangents_.clear();
    const bool mapped = std::any_of(materials_.begin(), materials_.end(),
                                    [](const Material& m) { return m.normal_texture >= 0; });
    if (!mapped || uvs_.empty()) return;
    tangents_.resize(12 * num_triangles());
    update_tangents(0, num_triangles());
}

void Scene::update_tangents(size_t first, size_t count) {
    if (tangents_.empty() || count == 0) return;
    const std::vector<float> part = corner_tangents(verts_.data(), tris_.data() + 3 * first, count,
                                                    normals_.empty() ? nullptr : normals_.data(),
                                                    uvs_.data() + 6 * first);
    std::copy(part.begin(), part.end(), tangents_.begin() + ptrdiff_t(12 * first));
}

namespace {

// The normal nearest n, in the plane of n and ng, whose mirror reflection of
// the direction to the viewer wo stays above the surface by at least
// min(0.9 wo.ng, 0.01) along ng (ng and n facing the viewer): a mapped normal
// turned away from the viewer would otherwise reflect into the surface, and
// light arriving from behind the surface's silhouette would reach it. Cycles
// corrects normal-mapped normals so. With n = sin(a) X + cos(a) ng (X the unit
// direction of n across ng), the reflection's height along ng is
// x sin(2a) + z cos(2a), with x = wo.X and z = wo.ng: = r cos(2a - b), with
// r = |(x, z)| and b = atan2(x, z). It reaches the threshold h for 2a within
// b +- acos(h / r); n is moved to the far end of that range, the one nearer it.
Vec3 reflecting_above(const Vec3& ng, const Vec3& wo, const Vec3& n) {
    const float z = dot(wo, ng);
    const float h = std::min(0.9f * z, 0.01f);
    if (dot(n * (2 * dot(n, wo)) - wo, ng) >= h) return n;
    Vec3 X = n - ng * dot(n, ng);
    const float xl = length(X);
    if (!(xl > 0)) return ng;
    X = X * (1.0f / xl);
    const float x = dot(wo, X);
    const float r = std::sqrt(x * x + z * z);
    if (!(r > 0) || h > r) return ng;
    // (ng itself, a = 0, reflects wo above the threshold, so n lies beyond
    // the range's far end: its near end is never the nearer one, though float
    // rounding could make it seem so)
    const float b = std::atan2(x, z), spread = std::acos(h / r);
    const float a = std::min(std::max(0.5f * (b + spread), 0.0f), 0.5f * float(kPi));
    return normalize(X * std::sin(a) + ng * std::cos(a));
}

}  // namespace

Vec3 Scene::normal_mapped(const Material& m, const Hit& hit, const SurfacePoint& sp, const TextureView& view) const {
    const Vec3 n = sp.ns;
    const Vec3& wo = view.wi;
    if (m.normal_texture < 0 || tangents_.empty()) return n;
    // The corners' tangents and signs interpolated, as Cycles interpolates
    // its tangent attribute; the tangent made orthogonal to the shading normal.
    const float* c = &tangents_[12 * size_t(hit.prim)];
    const float b0 = 1.0f - hit.u - hit.v;
    Vec3 T = Vec3(c[0], c[1], c[2]) * b0 + Vec3(c[4], c[5], c[6]) * hit.u + Vec3(c[8], c[9], c[10]) * hit.v;
    const float sign = c[3] * b0 + c[7] * hit.u + c[11] * hit.v < 0 ? -1.0f : 1.0f;
    T = T - n * dot(n, T);
    const float len = length(T);
    if (!(len > 0) || !std::isfinite(len)) return n;   // UVs of no area: no tangent
    T = T * (1.0f / len);
    const Vec3 B = cross(n, T) * sign;
    float u, v;
    hit_uv(hit, u, v);
    const Vec3 rgb = color_of(textures_[size_t(m.normal_texture)], lookup(m.normal_texture, hit, u, v, view));
    Vec3 mapped = T * (2 * rgb.x - 1) + B * (2 * rgb.y - 1) + n * (2 * rgb.z - 1);
    if (m.normal_strength != 1) mapped = n + (normalize(mapped) - n) * m.normal_strength;
    const float ml = length(mapped);
    if (!(ml > 0) || !std::isfinite(ml)) return n;
    mapped = mapped * (1.0f / ml);
    // (on the viewer's side of the surface, then back to sp's orientation)
    const float side = dot(sp.ng, wo) < 0 ? -1.0f : 1.0f;
    return reflecting_above(sp.ng * side, wo, mapped * side) * side;
}

bool Scene::corner_points(const Texture& t, size_t prim, const TextureView& view, Vec3 c[3]) const {
    if (t.kind == TextureKind::Attribute) {   // (the corners' values: the slope of their interpolation)
        if (colors_.empty() || prim >= num_triangles()) return false;
        for (int k = 0; k < 3; ++k) c[k] = Vec3(colors_[9 * prim + 3 * k], colors_[9 * prim + 3 * k + 1], colors_[9 * prim + 3 * k + 2]);
        return true;
    }
    if (t.kind == TextureKind::Image && t.projection == ImageProjection::Box) return false;   // (scene.h)
    if (t.coordinates == TextureCoords::UV) {
        if (uvs_.empty()) return false;
        for (int k = 0; k < 3; ++k) c[k] = Vec3(uvs_[6 * prim + 2 * k], uvs_[6 * prim + 2 * k + 1], 0);
        return true;
    }
    if (t.coordinates == TextureCoords::Position || t.coordinates == TextureCoords::Camera) {
        if (prim >= num_triangles()) return false;
        if (t.coordinates == TextureCoords::Camera && !view.camera) return false;
        for (int k = 0; k < 3; ++k) {
            c[k] = tri_verts_[3 * prim + size_t(k)];
            if (t.coordinates == TextureCoords::Camera) c[k] = view.camera->camera_point(c[k]);
        }
        return true;
    }
    if (t.coordinates != TextureCoords::Generated && t.coordinates != TextureCoords::Object) return false;
    const PooledVector<float>& values = corner_array(t.coordinates);
    if (values.empty()) return false;   // (check_generated refuses such a scene)
    for (int k = 0; k < 3; ++k) c[k] = Vec3(values[9 * prim + 3 * k], values[9 * prim + 3 * k + 1], values[9 * prim + 3 * k + 2]);
    return true;
}

bool Scene::pattern_slopes(const Texture& t, const Hit& hit, const TextureView& view, Vec3& T, Vec3& B, float& hu,
                           float& hv) const {
    const size_t prim = size_t(hit.prim);
    Vec3 c[3];
    if (!corner_points(t, prim, view, c)) return false;
    const Vec3* p = &tri_verts_[3 * prim];
    T = p[1] - p[0];
    B = p[2] - p[0];
    // The point and the directions in which it moves with the barycentrics of
    // corners 1 and 2 (after the Mapping's linear part); each slope a central
    // difference over a step of 1/1000 of the pattern's finest cells (1 / scale,
    // over lacunarity^detail for a fractal), or more where the point is so far
    // out that such a step would lose its digits.
    const float b0 = 1.0f - hit.u - hit.v;
    Vec3 q = c[0] * b0 + c[1] * hit.u + c[2] * hit.v, a1 = c[1] - c[0], a2 = c[2] - c[0];
    if (vector_mapped(t)) {
        q = map_vector(t, q);
        const Vec3 origin = map_vector(t, Vec3(0, 0, 0));
        a1 = map_vector(t, a1) - origin;
        a2 = map_vector(t, a2) - origin;
    }
    // (a White Noise is unscaled: its slopes are as rough as the step is small)
    const float cell = t.kind == TextureKind::Image ? 1.0f / float(std::max(images_[size_t(t.image)]->width(), 1))
                       : t.kind == TextureKind::Gradient || t.kind == TextureKind::WhiteNoise ||
                               t.kind == TextureKind::Attribute
                           ? 1.0f
                           : 1.0f / std::max(std::abs(t.scale), 1e-6f);
    // (a fractal's finest octave is lacunarity^detail times finer)
    const float finest = t.kind == TextureKind::Noise || t.kind == TextureKind::Voronoi
                             ? std::pow(std::max(t.lacunarity, 1.0f), std::ceil(std::min(std::max(t.detail, 0.0f), 15.0f)))
                             : 1.0f;
    const float far = std::max(std::abs(q.x), std::max(std::abs(q.y), std::abs(q.z)));
    const float delta = std::max(1e-3f * cell / finest, 1e-5f * far);
    auto slope = [&](const Vec3& a, float& out) {
        const float len = length(a);
        if (!(len > 0) || !std::isfinite(len)) return false;
        const float s = delta / len;
        const float up = scalar_of(t, pattern_at(t, q + a * s)), down = scalar_of(t, pattern_at(t, q - a * s));
        out = (up - down) / (2 * s);
        return std::isfinite(out);
    };
    return slope(a1, hu) && slope(a2, hv);
}

bool Scene::image_slopes(const Texture& t, const Hit& hit, Vec3& T, Vec3& B, float& hu, float& hv) const {
    if (uvs_.empty()) return false;
    const size_t prim = size_t(hit.prim);
    const Vec3* p = &tri_verts_[3 * prim];
    const float* uv = &uvs_[6 * prim];
    // dp/du and dp/dv of the triangle
    const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const float du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
    const float det = du1 * dv2 - du2 * dv1;
    if (!(det != 0)) return false;                       // UVs of no area
    T = (e1 * dv2 - e2 * dv1) * (1.0f / det);
    B = (e2 * du1 - e1 * du2) * (1.0f / det);
    // The height's slopes in the image's own coordinates (after uv_transform,
    // brought into the first tile where the image repeats, so that large UVs
    // keep their digits): central differences over a quarter of a texel of
    // its bilinear interpolation (Closest too: its steps have no slope to
    // take), then back to u and v through the transform's linear part.
    // (in the UDIM tile under the point, whose image's texels set the step; none: flat)
    Texture tex = t;
    tex.interpolation = Interpolation::Linear;
    float u, v;
    hit_uv(hit, u, v);
    float x = u, y = v;
    if (uv_mapped(tex)) map_uv(tex, x, y);
    const int32_t k = texture_image(tex, x, y);
    if (k < 0) return false;
    const Image& img = *images_[size_t(k)];
    const float period = tex.extension == Extension::Repeat ? 1.0f : tex.extension == Extension::Mirror ? 2.0f : 0.0f;
    if (period > 0 && std::isfinite(x) && std::isfinite(y)) {
        x -= period * std::floor(x / period);
        y -= period * std::floor(y / period);
    }
    const float sx = 0.25f / float(img.width()), sy = 0.25f / float(img.height());
    auto height = [&](float a, float b) { return scalar_of(tex, sample_image(img, tex, a, b)); };
    const float hx = (height(x + sx, y) - height(x - sx, y)) / (2 * sx);
    const float hy = (height(x, y + sy) - height(x, y - sy)) / (2 * sy);
    const auto& a = tex.uv_transform;
    hu = hx * a[0] + hy * a[3];
    hv = hx * a[1] + hy * a[4];
    return true;
}

Vec3 Scene::bumped(const Material& m, const Hit& hit, const Vec3& n, const TextureView& view) const {
    if (m.bump_texture < 0) return n;
    const Texture& tex = textures_[size_t(m.bump_texture)];
    Vec3 T, B;
    float hu, hv;
    if (!(plain_image(tex) ? image_slopes(tex, hit, T, B, hu, hv) : pattern_slopes(tex, hit, view, T, B, hu, hv))) return n;
    // The gradients of the two parameters along the triangle (the dual basis
    // of T and B in its plane: Mikkelsen's surface gradient) weighted by the slopes.
    const Vec3* p = &tri_verts_[3 * size_t(hit.prim)];
    const Vec3 ng = normalize(cross(p[1] - p[0], p[2] - p[0]));
    const float D = dot(ng, cross(T, B));
    if (!(std::abs(D) > 0) || !std::isfinite(D)) return n;
    Vec3 grad = (cross(B, ng) * hu + cross(ng, T) * hv) * (1.0f / D);
    // Its part along n removed along the geometric normal, as Cycles' Bump node
    // takes the surface's differentials against the shading normal: the vector
    // across n whose product with every direction along the surface is the
    // height's change that way. Then n bent by it, on n's own side.
    const float nn = dot(n, ng);
    if (!(std::abs(nn) > 1e-6f)) return n;
    grad = grad - ng * (dot(n, grad) / nn);
    Vec3 bent = normalize(n - grad * m.bump_distance);
    if (m.bump_strength != 1) bent = normalize(bent * m.bump_strength + n * (1 - m.bump_strength));
    if (!std::isfinite(bent.x) || !std::isfinite(bent.y) || !std::isfinite(bent.z)) return n;
    return bent;
}

Vec3 Scene::mapped_normal(const Material& m, const Hit& hit, const SurfacePoint& sp, const TextureView& view) const {
    if (size_t(hit.prim) >= num_triangles()) return sp.ns;
    return bumped(m, hit, normal_mapped(m, hit, sp, view), view);
}

float Scene::alpha_at(const Material& m, const Hit& hit, const TextureView& view) const {
    if (m.alpha_texture < 0) return m.alpha;
    float u, v;
    hit_uv(hit, u, v);
    return clamp01(scalar_of(textures_[size_t(m.alpha_texture)], lookup(m.alpha_texture, hit, u, v, view)));
}

size_t Scene::texture_bytes() const {
    size_t n = 0;
    for (const auto& img : images_) n += img ? img->memory_bytes() : 0;
    return n;
}

}  // namespace gw
