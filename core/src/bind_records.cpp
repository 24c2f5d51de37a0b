// Bindings of the scene records: gridwalk._core.Material, Light and Camera,
// one attribute per C++ field (the gridwalk package's dataclasses of the
// same names fill them field by field), and their validation.
#include <nanobind/nanobind.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bind_casters.h"
#include "bindings.h"
#include "noise.h"
#include "camera.h"
#include "lights.h"
#include "material.h"
#include "texture.h"
#include "world.h"

namespace nb = nanobind;

namespace gw {

void bind_records(nb::module_& m) {
    nb::class_<Material>(m, "Material")
        .def(nb::init<>())
        .def_rw("color", &Material::color)
        .def_rw("kd", &Material::kd)
        .def_rw("ks", &Material::ks)
        .def_rw("shininess", &Material::shininess)
        .def_rw("transmittance", &Material::transmittance)
        .def_rw("ior", &Material::ior)
        .def_rw("mirror", &Material::mirror)
        .def_rw("metallic", &Material::metallic)
        .def_rw("roughness", &Material::roughness)
        .def_rw("emission", &Material::emission)
        .def_rw("emission_color", &Material::emission_color)
        .def_rw("alpha", &Material::alpha)
        .def_rw("color_texture", &Material::color_texture)
        .def_rw("roughness_texture", &Material::roughness_texture)
        .def_rw("metallic_texture", &Material::metallic_texture)
        .def_rw("alpha_texture", &Material::alpha_texture)
        .def_rw("normal_texture", &Material::normal_texture)
        .def_rw("normal_strength", &Material::normal_strength)
        .def_rw("emission_texture", &Material::emission_texture)
        .def_rw("bump_texture", &Material::bump_texture)
        .def_rw("bump_distance", &Material::bump_distance)
        .def_rw("bump_strength", &Material::bump_strength)
        .def_rw("vertex_color", &Material::vertex_color)
        .def_rw("tints_refraction", &Material::tints_refraction)
        .def_rw("tints_reflection", &Material::tints_reflection)
        .def_rw("multiscatter", &Material::multiscatter)
        .def_rw("dielectric_reflection", &Material::dielectric_reflection)
        .def_rw("layered_diffuse", &Material::layered_diffuse)
        .def_rw("emits_light", &Material::emits_light)
        .def_rw("holdout", &Material::holdout)
        .def_rw("holdout_camera", &Material::holdout_camera)
        .def_rw("shadow_catcher", &Material::shadow_catcher)
        .def_rw("visible_camera", &Material::visible_camera)
        .def_rw("visible_glossy", &Material::visible_glossy)
        .def_rw("visible_transmission", &Material::visible_transmission)
        .def_rw("visible_shadow", &Material::visible_shadow)
        .def("validate", [](const Material& mat) { validate_material(mat, "Material"); });

    nb::class_<Texture>(m, "Texture")
        .def(nb::init<>())
        .def_rw("kind", &Texture::kind)
        .def_rw("image", &Texture::image)
        .def_rw("coordinates", &Texture::coordinates)
        .def_rw("vector_transform", &Texture::vector_transform)
        .def_rw("color1", &Texture::color1)
        .def_rw("color2", &Texture::color2)
        .def_rw("scale", &Texture::scale)
        .def_rw("gradient", &Texture::gradient)
        .def_rw("noise_type", &Texture::noise_type)
        .def_rw("dimensions", &Texture::dimensions)
        .def_rw("w", &Texture::w)
        .def_rw("detail", &Texture::detail)
        .def_rw("roughness", &Texture::roughness)
        .def_rw("lacunarity", &Texture::lacunarity)
        .def_rw("distortion", &Texture::distortion)
        .def_rw("noise_offset", &Texture::noise_offset)
        .def_rw("noise_gain", &Texture::noise_gain)
        .def_rw("normalize", &Texture::normalize)
        .def_rw("noise_wrap", &Texture::noise_wrap)
        .def_rw("voronoi_feature", &Texture::voronoi_feature)
        .def_rw("voronoi_metric", &Texture::voronoi_metric)
        .def_rw("voronoi_output", &Texture::voronoi_output)
        .def_rw("exponent", &Texture::exponent)
        .def_rw("randomness", &Texture::randomness)
        .def_rw("smoothness", &Texture::smoothness)
        .def_rw("voronoi_pcg", &Texture::voronoi_pcg)
        .def_rw("wave_type", &Texture::wave_type)
        .def_rw("wave_direction", &Texture::wave_direction)
        .def_rw("wave_profile", &Texture::wave_profile)
        .def_rw("detail_scale", &Texture::detail_scale)
        .def_rw("phase", &Texture::phase)
        .def_rw("depth", &Texture::depth)
        .def_rw("mortar", &Texture::mortar)
        .def_rw("mortar_size", &Texture::mortar_size)
        .def_rw("mortar_smooth", &Texture::mortar_smooth)
        .def_rw("brick_bias", &Texture::brick_bias)
        .def_rw("brick_width", &Texture::brick_width)
        .def_rw("row_height", &Texture::row_height)
        .def_rw("offset_amount", &Texture::offset_amount)
        .def_rw("squash_amount", &Texture::squash_amount)
        .def_rw("offset_frequency", &Texture::offset_frequency)
        .def_rw("squash_frequency", &Texture::squash_frequency)
        .def_rw("ramp", &Texture::ramp)
        .def_rw("ramp_interpolation", &Texture::ramp_interpolation)
        .def_rw("interpolation", &Texture::interpolation)
        .def_rw("extension", &Texture::extension)
        .def_rw("projection", &Texture::projection)
        .def_rw("projection_blend", &Texture::projection_blend)
        .def_rw("use_alpha", &Texture::use_alpha)
        .def_rw("premultiply", &Texture::premultiply)
        .def_rw("unassociate", &Texture::unassociate)
        .def_rw("uv_transform", &Texture::uv_transform)
        .def_rw("channel", &Texture::channel)
        .def_rw("gain", &Texture::gain)
        .def_rw("bias", &Texture::bias)
        .def_rw("clamp", &Texture::clamp)
        .def_rw("ramp_channel", &Texture::ramp_channel)
        .def_rw("ramp_gain", &Texture::ramp_gain)
        .def_rw("ramp_bias", &Texture::ramp_bias)
        .def_rw("ramp_clamp", &Texture::ramp_clamp)
        .def("validate", [](const Texture& t) { validate_texture(t, "Texture"); });
    m.def("signed_noise", [](const std::vector<float>& x, bool wrap) {
        if (x.empty() || x.size() > 4) throw std::invalid_argument("signed_noise takes 1 to 4 coordinates");
        return signed_noise(int(x.size()), x.data(), wrap);
    }, nb::arg("x"), nb::arg("wrap") = true);

    nb::class_<World>(m, "World")
        .def(nb::init<>())
        .def_rw("ambient", &World::ambient)
        .def_rw("environment", &World::environment)
        .def_rw("environment_strength", &World::environment_strength)
        .def_rw("environment_light", &World::environment_light)
        .def_rw("environment_rotation", &World::environment_rotation)
        .def_rw("transparent", &World::transparent)
        .def_rw("inset", &World::inset)
        .def_rw("inset_frame", &World::inset_frame)
        .def_rw("inset_extent", &World::inset_extent)
        .def("validate", &validate_world);

    nb::class_<Light>(m, "Light")
        .def(nb::init<>())
        .def_rw("kind", &Light::kind)
        .def_rw("position", &Light::position)
        .def_rw("color", &Light::color)
        .def_rw("radius", &Light::radius)
        .def_rw("size", &Light::size)
        .def_rw("axis_u", &Light::axis_u)
        .def_rw("axis_v", &Light::axis_v)
        .def_rw("direction", &Light::direction)
        .def_rw("angle", &Light::angle)
        .def_rw("spot_size", &Light::spot_size)
        .def_rw("spot_blend", &Light::spot_blend)
        .def_rw("inverse_square", &Light::inverse_square)
        .def_rw("casts_shadows", &Light::casts_shadows)
        .def_rw("soft_falloff", &Light::soft_falloff)
        .def("validate", [](const Light& l) { Light copy = l; prepare_light(copy, "Light"); });

    nb::class_<CameraDesc>(m, "Camera")
        .def(nb::init<>())
        .def_rw("eye", &CameraDesc::eye)
        .def_rw("target", &CameraDesc::target)
        .def_rw("up", &CameraDesc::up)
        .def_rw("projection", &CameraDesc::projection)
        .def_rw("fov", &CameraDesc::fov)
        .def_rw("ortho_height", &CameraDesc::ortho_height)
        .def_rw("width", &CameraDesc::width)
        .def_rw("height", &CameraDesc::height)
        .def_rw("pixel_aspect", &CameraDesc::pixel_aspect)
        .def_rw("aperture", &CameraDesc::aperture)
        .def_rw("focus_distance", &CameraDesc::focus_distance)
        .def_rw("blades", &CameraDesc::blades)
        .def_rw("blade_rotation", &CameraDesc::blade_rotation)
        .def_rw("aperture_ratio", &CameraDesc::aperture_ratio)
        .def_rw("shift", &CameraDesc::shift)
        .def_rw("longitude", &CameraDesc::longitude)
        .def_rw("latitude", &CameraDesc::latitude)
        .def_rw("window", &CameraDesc::window)
        .def_rw("fisheye_fov", &CameraDesc::fisheye_fov)
        .def_rw("fisheye_lens", &CameraDesc::fisheye_lens)
        .def_rw("sensor", &CameraDesc::sensor)
        .def_rw("polynomial", &CameraDesc::polynomial)
        .def_rw("cylinder_height", &CameraDesc::cylinder_height)
        .def_rw("hither", &CameraDesc::hither)
        .def_rw("origin_ahead", &CameraDesc::origin_ahead)
        .def_rw("yon", &CameraDesc::yon)
        .def_rw("mirror", &CameraDesc::mirror)
        .def("validate", &validate_camera);
}

}  // namespace gw
