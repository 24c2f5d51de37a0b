// The Whitted material record (NFF's `f r g b Kd Ks Shine T ior`, plus a
// mirror weight, a glossy roughness and an emission strength), with what
// Blender's artists set on top: an emitted colour, an alpha (coverage), and
// textures (indices into the scene's textures, -1 = none) or the mesh's
// colour attribute for the inputs they drive. Bound to Python field by field
// as gridwalk._core.Material.
#pragma once
#include <string>

#include "math.h"
#include "ray.h"

namespace gw {

struct Material {
    Vec3 color{1, 1, 1};
    float kd = 0.8f, ks = 0, shininess = 32, transmittance = 0, ior = 1, mirror = 0, roughness = 0, emission = 0;
    Vec3 emission_color{0, 0, 0};   // emitted radiance, added to color * emission
    float alpha = 1;                // coverage: 1 opaque, 0 invisible (see-through to every ray)
    // How much of the surface is metal (Principled Metallic): that share of
    // the specular highlight (metallic * (shininess + 8) / (8 ks) of it) and of
    // the mirror reflection takes the base colour, as a metal's reflection does.
    float metallic = 0;
    // With own_metal_color, the metal share takes metal_color instead of the
    // base colour (a Mix Shader of a Diffuse BSDF and a Glossy BSDF of another
    // colour: the base colour is the diffuse's, metal_color the glossy's).
    bool own_metal_color = false;
    Vec3 metal_color{1, 1, 1};
    int32_t color_texture = -1, roughness_texture = -1, metallic_texture = -1, alpha_texture = -1;
    // The base colour is the mesh's per-corner colour (colour attribute); with a
    // color_texture, the texture's colour times it.
    bool vertex_color = false;
    // A tangent-space normal map (Blender's Normal Map node): the texture's
    // RGB in [0, 1] is a normal in the frame of the triangle's UV tangent, its
    // bitangent and the shading normal; strength blends from the shading
    // normal (0) to the mapped one (1) and beyond, as Cycles does.
    int32_t normal_texture = -1;
    float normal_strength = 1;
    // The emitted colour varies over the surface: this texture's colour times
    // emission_color (Principled's Emission Color fed by an image,
    // emission_color holding its Emission Strength).
    int32_t emission_texture = -1;
    // A bump map (Blender's Bump node fed by a height texture): the shading
    // normal n becomes normalize(n - bump_distance x the surface gradient of
    // the height, its part along n removed along the geometric normal), then
    // is blended with n by bump_strength (0 none, 1 all). A negative distance
    // bumps inwards (the node's Invert).
    int32_t bump_texture = -1;
    float bump_distance = 1, bump_strength = 1;
    // Its triangles light other surfaces with what they emit (emitters.h), as
    // area lights do; without it emission is only seen.
    bool emits_light = false;
    // The colour tints the light the surface refracts (Cycles' Principled
    // transmission and Glass BSDF: coloured glass), also along shadow rays
    // through it, and with tints_reflection what it reflects too (the Glass
    // BSDF). NFF's transmission (and Whitted's) is not tinted.
    bool tints_refraction = false, tints_reflection = false;
    // With tints_refraction: each crossing tints by the colour's square root, so that light
    // entering and leaving a closed object is tinted by the colour (Cycles 4.0+'s Principled BSDF;
    // its Glass BSDF, and 3.x's Principled, tint by the colour at each crossing).
    bool tint_sqrt = false;
    // A glossy surface's (roughness > 0) GGX lobe gets back the energy single
    // scattering loses, as Cycles' Multiscatter GGX (microfacet.h).
    bool multiscatter = false;
    // The specular layer of the surface's dielectric share (neither mirror nor
    // transmittance) reflects the scene as well as the lamps: reflection rays
    // weighted by the exact Fresnel of the IOR whose reflectance at normal
    // incidence is the specular weight's non-metal part (ks * 8 / (shininess
    // + 8) less metallic, per unit of non-metal), along
    // the GGX lobe of the roughness, as Cycles' Principled BSDF does. NFF's
    // Phong highlight reflects only the lamps.
    bool dielectric_reflection = false;
    // The diffuse lies under that layer and gets what the layer does not
    // reflect as seen from the viewer: kd times 1 - the layer's albedo in the
    // view direction (Blender 4.0+'s Principled BSDF); without it the layer
    // adds to the diffuse (3.x's Principled, NFF).
    bool layered_diffuse = false;
    // A holdout (Cycles' Holdout shader, an object or collection set to
    // Holdout): camera rays that meet it see nothing (black) and leave the
    // film transparent there (RenderJob.holdout: the share of each pixel);
    // other rays see it black; it blocks light as an opaque surface does.
    bool holdout = false;
    // Held out from camera rays only (an object or collection set to Holdout in
    // Blender): other rays see the material, and its alpha cut-outs stay.
    bool holdout_camera = false;
    // A shadow catcher (an object's Shadow Catcher in Blender): camera rays see
    // what lies behind it (the world, or what it hides) darkened by the share of
    // light the scene keeps from it, its diffuse light with shadows over its light
    // without them, per channel; on a transparent film, that shadow is coverage
    // (alpha 1 - the share, black), for compositing over footage. Other rays see
    // the material, and it casts shadows.
    bool shadow_catcher = false;
    // Which rays see it (an object's Visibility in Blender): camera rays (and
    // what continues them through see-through surfaces), glossy reflection
    // and transmission (refraction) rays pass through a surface hidden from
    // them as through an alpha cut-out, shadow rays through one that casts
    // no shadow.
    bool visible_camera = true, visible_glossy = true, visible_transmission = true, visible_shadow = true;

    // Whether anything varies over the surface (textures, colour attribute):
    // only such materials are re-evaluated per hit.
    bool varies() const {
        return color_texture >= 0 || roughness_texture >= 0 || metallic_texture >= 0 || alpha_texture >= 0 ||
               emission_texture >= 0 || vertex_color;
    }
    // Whether it lets light through (shadow rays are attenuated, not stopped).
    bool lets_light_through() const { return transmittance > 0 || alpha < 1 || alpha_texture >= 0 || !visible_shadow; }
    bool seen_by(RayKind kind) const {
        return kind == RayKind::Camera ? visible_camera
             : kind == RayKind::Glossy ? visible_glossy
             : kind == RayKind::Transmission ? visible_transmission : true;
    }
};

// The colour the metal share of material m reflects (see own_metal_color).
inline Vec3 metal_color_of(const Material& m) { return m.own_metal_color ? m.metal_color : m.color; }

// What a crossing of material m's surface tints refracted light by (see tints_refraction).
inline Vec3 refraction_tint(const Material& m) {
    if (!m.tints_refraction) return Vec3(1, 1, 1);
    if (!m.tint_sqrt) return m.color;
    auto root = [](float x) { return x > 0 ? std::sqrt(x) : 0.0f; };
    return Vec3(root(m.color.x), root(m.color.y), root(m.color.z));
}

// Throws std::invalid_argument naming `where` (e.g. "materials[2]") and the field.
void validate_material(const Material& m, const std::string& where);

}  // namespace gw
