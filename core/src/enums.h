// Named enumerations, declared once. Each list row is one value: its C++
// name, the identifier Python, the CLI and Blender use for it, a label and
// a help line. GW_ENUM turns a list into the enum class, its item table and
// EnumTraits, from which the bindings export both the enum and its items.
#pragma once
#include <cstddef>

namespace gw {

struct EnumItem {
    const char* id;      // "jittered": the value in Python, on the CLI, lower-cased in Blender's enum ids
    const char* label;   // "Jittered": Blender's label
    const char* help;    // one line
};

template <class E>
struct EnumTraits;   // ::name, ::items, ::count

#define GW_ENUM_VALUE(value, id, label, help) value,
#define GW_ENUM_ITEM(value, id, label, help) EnumItem{id, label, help},
#define GW_ENUM(Type, LIST)                                                    \
    enum class Type : int { LIST(GW_ENUM_VALUE) };                              \
    template <>                                                                \
    struct EnumTraits<Type> {                                                  \
        static constexpr const char* name = #Type;                             \
        static constexpr EnumItem items[] = {LIST(GW_ENUM_ITEM)};              \
        static constexpr int count = int(sizeof(items) / sizeof(items[0]));    \
    };

template <class E>
inline bool enum_valid(E e) { return int(e) >= 0 && int(e) < EnumTraits<E>::count; }
template <class E>
inline const char* enum_id(E e) { return enum_valid(e) ? EnumTraits<E>::items[int(e)].id : "?"; }

// --- the enumerations ---------------------------------------------------------

#define GW_ACCEL_KINDS(X)                                                                          \
    X(None, "none", "None", "Test every primitive (brute force, the seed's no-grid column)")      \
    X(Grid, "grid", "Uniform Grid", "The seed's uniform grid, walked with Amanatides & Woo's DDA")   \
    X(Adaptive, "adaptive", "Adaptive Grid",                                                       \
      "Uniform grids refined where the primitives crowd, each walked with the DDA; SIMD triangle tests")
GW_ENUM(AccelKind, GW_ACCEL_KINDS)

#define GW_AA_MODES(X)                                                                    \
    X(Center, "center", "Pixel Centre", "One ray through each pixel centre")              \
    X(Jittered, "jittered", "Jittered", "Stratified n x n jittered samples per pixel")    \
    X(Random, "random", "Random", "n x n uniformly random samples per pixel")             \
    X(Adaptive, "adaptive", "Adaptive", "Whitted's adaptive supersampling: trace the corners, subdivide where they differ") \
    X(Sobol, "sobol", "Sobol", "n x n Owen-scrambled Sobol (low-discrepancy) samples per pixel")
GW_ENUM(AAMode, GW_AA_MODES)

#define GW_SHADOW_MODES(X)                                                                          \
    X(Hard, "hard", "Hard", "One shadow ray to each light's centre")                               \
    X(Random, "random", "Random", "A random point on the light per shadow ray")                    \
    X(Area, "area", "Area", "The seed's area light: an n x n jittered grid of light positions, shuffled per pixel")
GW_ENUM(ShadowMode, GW_SHADOW_MODES)

#define GW_PIXEL_FILTERS(X)                                    \
    X(Box, "box", "Box", "Box pixel filter")                    \
    X(Gaussian, "gaussian", "Gaussian", "Gaussian pixel filter (filter_width is its standard deviation)")
GW_ENUM(PixelFilter, GW_PIXEL_FILTERS)

#define GW_INSTANCING_MODES(X)                                                                       \
    X(Off, "off", "Off", "One grid over every copy's triangles")                                     \
    X(Auto, "auto", "Auto",                                                                          \
      "The instanced grid where copies make at least half of the primitives and over 2^20 triangles "\
      "(below, the flat grid builds fast and traces faster)")                                        \
    X(On, "on", "On", "The instanced grid wherever a declared copy checks out")
GW_ENUM(Instancing, GW_INSTANCING_MODES)

#define GW_LIGHT_KINDS(X)                                                                        \
    X(Point, "point", "Point", "A point (a sphere light when its radius is > 0)")                \
    X(Sphere, "sphere", "Sphere", "A sphere of the given radius (soft shadows)")                 \
    X(Rect, "rect", "Rectangle", "A one-sided rectangle of the given size, emitting along direction") \
    X(Disk, "disk", "Disk", "A one-sided disk of the given radius, emitting along direction")    \
    X(Sun, "sun", "Sun", "A direction, with an angular diameter for soft shadows")              \
    X(Spot, "spot", "Spot", "A point emitting in a cone around direction")                     \
    X(Ellipse, "ellipse", "Ellipse", "A one-sided ellipse whose diameters along axis_u, axis_v are size, emitting along direction")
GW_ENUM(LightKind, GW_LIGHT_KINDS)

#define GW_PROJECTIONS(X)                                                                                   \
    X(Perspective, "perspective", "Perspective", "A pinhole (or thin lens) camera; fov is the vertical angle") \
    X(Orthographic, "orthographic", "Orthographic", "Parallel rays; ortho_height is the view's height")      \
    X(Equirectangular, "equirectangular", "Equirectangular",                                                  \
      "A panorama: x spans the longitude range, y the latitude range")                                      \
    X(FisheyeEquidistant, "fisheye_equidistant", "Fisheye Equidistant",                                      \
      "A circular fisheye filling the image: the angle from the view axis grows with the radius up to fisheye_fov / 2") \
    X(FisheyeEquisolid, "fisheye_equisolid", "Fisheye Equisolid",                                            \
      "A real fisheye lens (radius 2 fisheye_lens sin(angle / 2) on the sensor), cut at fisheye_fov")          \
    X(FisheyePolynomial, "fisheye_polynomial", "Fisheye Lens Polynomial",                                    \
      "A fitted lens: the angle from the view axis is -(k0 + k1 r + ... + k4 r^4), r in mm on the sensor")    \
    X(MirrorBall, "mirror_ball", "Mirror Ball", "The world as a mirrored sphere in front of the camera reflects it") \
    X(CubemapFace, "cubemap_face", "Equiangular Cubemap Face",                                               \
      "One 90 x 90 degree face of an equiangular cube map")                                                  \
    X(CentralCylindrical, "central_cylindrical", "Central Cylindrical",                                     \
      "A cylinder around the camera: x spans the longitude range, y the cylinder_height range")
GW_ENUM(Projection, GW_PROJECTIONS)

#define GW_INTERPOLATIONS(X)                                                                  \
    X(Linear, "linear", "Linear", "Bilinear interpolation of the four nearest texels")        \
    X(Closest, "closest", "Closest", "The nearest texel (pixel art, data maps)")
GW_ENUM(Interpolation, GW_INTERPOLATIONS)

#define GW_EXTENSIONS(X)                                                                      \
    X(Repeat, "repeat", "Repeat", "Tile the image in both directions")                        \
    X(Extend, "extend", "Extend", "Repeat the edge texels outside the image")                 \
    X(Clip, "clip", "Clip", "Transparent black outside the image")                             \
    X(Mirror, "mirror", "Mirror", "Tile the image, every other tile mirrored")
GW_ENUM(Extension, GW_EXTENSIONS)

#define GW_IMAGE_PROJECTIONS(X)                                                                         \
    X(Flat, "flat", "Flat", "The point's (x, y)")                                                       \
    X(Box, "box", "Box", "Three flat projections along the object's axes, blended by its normal")       \
    X(Sphere, "sphere", "Sphere", "Longitude and latitude of the point about the centre of its unit box") \
    X(Tube, "tube", "Tube", "Angle about the unit box's z axis, and height along it")
GW_ENUM(ImageProjection, GW_IMAGE_PROJECTIONS)

#define GW_TEXTURE_KINDS(X)                                                                              \
    X(Image, "image", "Image", "An image, looked up at the texture coordinates")                           \
    X(Checker, "checker", "Checker", "Blender's Checker Texture: color1 and color2 in alternating cubes of 1 / scale") \
    X(Gradient, "gradient", "Gradient", "Blender's Gradient Texture: a grey ramp of the point, shaped by gradient") \
    X(Noise, "noise", "Noise", "Blender's Noise Texture: Perlin noise of the point, summed over octaves (noise_type)") \
    X(Voronoi, "voronoi", "Voronoi", "Blender's Voronoi Texture: the nearest of points scattered one per cell (voronoi_feature)") \
    X(Wave, "wave", "Wave", "Blender's Wave Texture: bands or rings (wave_type), distorted by noise")        \
    X(Magic, "magic", "Magic", "Blender's Magic Texture: nested sines and cosines of the point (depth)")     \
    X(WhiteNoise, "white_noise", "White Noise", "Blender's White Noise Texture: a hashed value per point")   \
    X(Brick, "brick", "Brick", "Blender's Brick Texture: rows of bricks of two tinted colours in mortar") \
    X(Attribute, "attribute", "Attribute",                                                                 \
      "Blender's Attribute node: the triangles' corner colours (Scene(colors=...)) at the hit, alpha their mean")
GW_ENUM(TextureKind, GW_TEXTURE_KINDS)

#define GW_WAVE_TYPES(X)                                                                                   \
    X(Bands, "bands", "Bands", "Parallel bands across wave_direction (x, y, z or diagonal)")              \
    X(Rings, "rings", "Rings", "Rings about the axis wave_direction names (x, y, z), or spheres (spherical)")
GW_ENUM(WaveType, GW_WAVE_TYPES)

#define GW_WAVE_DIRECTIONS(X)                                                                              \
    X(AxisX, "x", "X", "Bands across x; rings about the x axis")                                               \
    X(AxisY, "y", "Y", "Bands across y; rings about the y axis")                                               \
    X(AxisZ, "z", "Z", "Bands across z; rings about the z axis")                                               \
    X(Diagonal, "diagonal", "Diagonal", "Bands across x + y + z (bands only)")                             \
    X(Spherical, "spherical", "Spherical", "Spheres about the origin (rings only)")
GW_ENUM(WaveDirection, GW_WAVE_DIRECTIONS)

#define GW_WAVE_PROFILES(X)                                                                                \
    X(Sine, "sine", "Sine", "A smooth wave from 0 to 1 and back")                                          \
    X(Saw, "saw", "Saw", "Rising from 0 to 1, then dropping")                                              \
    X(Triangle, "triangle", "Triangle", "Rising from 0 to 1 and falling again, in straight lines")
GW_ENUM(WaveProfile, GW_WAVE_PROFILES)

#define GW_VORONOI_FEATURES(X)                                                                            \
    X(F1, "f1", "F1", "The nearest point")                                                                  \
    X(F2, "f2", "F2", "The second nearest point")                                                           \
    X(SmoothF1, "smooth_f1", "Smooth F1", "The nearest point, blended with the others by smoothness")     \
    X(DistanceToEdge, "distance_to_edge", "Distance to Edge", "The distance to the nearest cell border")  \
    X(NSphereRadius, "n_sphere_radius", "N-Sphere Radius", "Half the distance from the nearest point to its nearest")
GW_ENUM(VoronoiFeature, GW_VORONOI_FEATURES)

#define GW_VORONOI_METRICS(X)                                                                             \
    X(Euclidean, "euclidean", "Euclidean", "The straight distance")                                        \
    X(Manhattan, "manhattan", "Manhattan", "The sum of the distances along the axes")                     \
    X(Chebychev, "chebychev", "Chebychev", "The largest of the distances along the axes")                 \
    X(Minkowski, "minkowski", "Minkowski", "(sum of |d|^exponent)^(1 / exponent)")
GW_ENUM(VoronoiMetric, GW_VORONOI_METRICS)

#define GW_VORONOI_OUTPUTS(X)                                                                             \
    X(Distance, "distance", "Distance", "The distance to the point, as grey")                              \
    X(Color, "color", "Color", "The point's cell's random colour")                                         \
    X(Position, "position", "Position", "The point's position (x, y, z)")                                  \
    X(W, "w", "W", "The point's fourth coordinate, as grey")                                               \
    X(Radius, "radius", "Radius", "The n-sphere radius (feature n_sphere_radius), as grey")
GW_ENUM(VoronoiOutput, GW_VORONOI_OUTPUTS)

#define GW_NOISE_TYPES(X)                                                                                   \
    X(Fbm, "fbm", "fBM", "Fractal Brownian motion: the octaves added, each roughness times the last")       \
    X(Multifractal, "multifractal", "Multifractal", "The octaves multiplied")                               \
    X(HybridMultifractal, "hybrid_multifractal", "Hybrid Multifractal", "Added, each weighted by the ones before (offset, gain)") \
    X(RidgedMultifractal, "ridged_multifractal", "Ridged Multifractal", "Ridges where the noise crosses 0 (offset, gain)") \
    X(HeteroTerrain, "hetero_terrain", "Hetero Terrain", "Added, each weighted by the value so far (offset)")
GW_ENUM(NoiseType, GW_NOISE_TYPES)

#define GW_GRADIENTS(X)                                                                                   \
    X(Linear, "linear", "Linear", "x")                                                                      \
    X(Quadratic, "quadratic", "Quadratic", "max(x, 0) squared")                                             \
    X(Easing, "easing", "Easing", "x clamped to [0, 1], eased: 3 x^2 - 2 x^3")                             \
    X(Diagonal, "diagonal", "Diagonal", "(x + y) / 2")                                                      \
    X(Spherical, "spherical", "Spherical", "1 - the distance from the origin, from 0")                     \
    X(QuadraticSphere, "quadratic_sphere", "Quadratic Sphere", "spherical, squared")                       \
    X(Radial, "radial", "Radial", "the angle about z, a turn from -x round to -x again")
GW_ENUM(Gradient, GW_GRADIENTS)

#define GW_RAMP_INTERPOLATIONS(X)                                                                         \
    X(Linear, "linear", "Linear", "Straight lines between the stops' colours")                             \
    X(Ease, "ease", "Ease", "Between two stops t eased to 3 t^2 - 2 t^3")                                  \
    X(Constant, "constant", "Constant", "Each stop's colour up to the next stop")
GW_ENUM(RampInterpolation, GW_RAMP_INTERPOLATIONS)

#define GW_TEXTURE_COORDS(X)                                                                                \
    X(UV, "uv", "UV", "The triangles' UV map (u, v, 0)")                                                    \
    X(Generated, "generated", "Generated",                                                                  \
      "Blender's Generated coordinates: the object's own position in its texture space, 0..1 across its box") \
    X(Object, "object", "Object", "Blender's Object coordinates: the point in its object's own space")       \
    X(Position, "position", "Position",                                                                     \
      "The point in world space (Blender's Geometry Position; through vector_transform, another object's "  \
      "Object coordinates)")                                                                                \
    X(Normal, "normal", "Normal",                                                                           \
      "Blender's Normal coordinates: the shading normal in its object's own space, from Scene(object_normals=...)") \
    X(Camera, "camera", "Camera",                                                                           \
      "Blender's Camera coordinates: the point in the rendering camera's space (x right, y up, z forward)")  \
    X(Window, "window", "Window",                                                                           \
      "Blender's Window coordinates: the point's place in the image, 0..1 from its bottom-left corner")      \
    X(Reflection, "reflection", "Reflection",                                                               \
      "Blender's Reflection coordinates: the view direction mirrored about the shading normal, world space") \
    X(GeometryNormal, "geometry_normal", "Geometry Normal",                                                 \
      "Blender's Geometry node's Normal: the shading normal in world space, turned over on a back face")     \
    X(TrueNormal, "true_normal", "True Normal",                                                             \
      "Blender's Geometry node's True Normal: the geometric normal in world space, turned over on a back face") \
    X(Incoming, "incoming", "Incoming",                                                                     \
      "Blender's Geometry node's Incoming: the unit direction back along the ray, world space")
GW_ENUM(TextureCoords, GW_TEXTURE_COORDS)

}  // namespace gw
