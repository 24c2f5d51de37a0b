// The scene's textures: checking them where they enter, the texture
// coordinates of a hit, and materials evaluated at a hit. See scene.h.
#include <stdexcept>

#include "scene.h"

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
    for (size_t i = 0; i < images_.size(); ++i)
        if (!images_[i]) bad("images[" + std::to_string(i) + "] is missing");
    for (size_t i = 0; i < textures_.size(); ++i) {
        const std::string where = "textures[" + std::to_string(i) + "]";
        validate_texture(textures_[i], where);
        const int32_t k = textures_[i].image;
        if (k < 0 || size_t(k) >= images_.size())
            bad(where + ".image = " + std::to_string(k) + " is out of range: images has " +
                std::to_string(images_.size()) + " entries");
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
        transparent_shadows_ = transparent_shadows_ || m.lets_light_through();
    }
    validate_world(world_);
    check_index(world_.environment, "World.environment");
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

void Scene::hit_uv(const Hit& hit, float& u, float& v) const {
    u = v = 0;
    if (uvs_.empty() || size_t(hit.prim) >= num_triangles()) return;
    const float* t = &uvs_[6 * size_t(hit.prim)];
    const float b0 = 1.0f - hit.u - hit.v;
    u = b0 * t[0] + hit.u * t[2] + hit.v * t[4];
    v = b0 * t[1] + hit.u * t[3] + hit.v * t[5];
}

Material Scene::shade(const Material& m, const Hit& hit) const {
    Material out = m;
    float u, v;
    hit_uv(hit, u, v);
    if (m.color_texture >= 0) {
        out.color = color_of(textures_[size_t(m.color_texture)], lookup(m.color_texture, u, v));
    } else if (m.vertex_color && !colors_.empty() && size_t(hit.prim) < num_triangles()) {
        const float* c = &colors_[9 * size_t(hit.prim)];
        const float b0 = 1.0f - hit.u - hit.v;
        out.color = Vec3(c[0], c[1], c[2]) * b0 + Vec3(c[3], c[4], c[5]) * hit.u + Vec3(c[6], c[7], c[8]) * hit.v;
    }
    if (m.roughness_texture >= 0) {
        const float r = clamp01(scalar_of(textures_[size_t(m.roughness_texture)], lookup(m.roughness_texture, u, v)));
        out.shininess = shininess_of(r);
        out.ks = m.ks * (out.shininess + 8.0f) / (m.shininess + 8.0f);   // same specular weight, new lobe
        out.roughness = r;
    }
    if (m.metallic_texture >= 0) {
        // The record holds the non-metal (metallic = 0) mapping; blend towards the metal.
        const float mt = clamp01(scalar_of(textures_[size_t(m.metallic_texture)], lookup(m.metallic_texture, u, v)));
        const float norm = (out.shininess + 8.0f) / 8.0f, f0 = out.ks / norm;
        out.kd = m.kd * (1 - mt);
        out.transmittance = m.transmittance * (1 - mt);
        out.mirror = mt;
        out.metallic = mt;
        out.ks = ((1 - mt) * f0 + mt) * norm;
    }
    if (m.alpha_texture >= 0) out.alpha = alpha_at(m, hit);
    return out;
}

float Scene::alpha_at(const Material& m, const Hit& hit) const {
    if (m.alpha_texture < 0) return m.alpha;
    float u, v;
    hit_uv(hit, u, v);
    return clamp01(scalar_of(textures_[size_t(m.alpha_texture)], lookup(m.alpha_texture, u, v)));
}

size_t Scene::texture_bytes() const {
    size_t n = 0;
    for (const auto& img : images_) n += img ? img->memory_bytes() : 0;
    return n;
}

}  // namespace gw
