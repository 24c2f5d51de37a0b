// Render settings, declared once.
//
// Each row of GW_RENDER_SETTINGS is one setting: its C++ type, name,
// default, inclusive limits, the group hosts show it in, when it matters
// ("aa=adaptive": only for that value of another setting; "" always), a
// label and a help line. Everything else is derived from this table: the
// RenderSettings struct, validate_settings(), and the schema the bindings
// export (gridwalk._core.settings_schema), from which gridwalk.RenderSettings,
// the CLI options and the Blender properties and panels are built.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

#include "enums.h"

namespace gw {

// Part of the image to render, in pixels, row 0 at the top; w = 0: all of it.
struct Region {
    int x = 0, y = 0, w = 0, h = 0;
};

constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// X(type, name, default, min, max, group, when, label, help)
#define GW_RENDER_SETTINGS(X)                                                                                      \
    X(AccelKind, accel, AccelKind::Adaptive, 0, 0, "acceleration", "", "Acceleration",                                 \
      "How rays find the primitives they hit")                                                                     \
    X(double, grid_density, 2.0, 0.01, 1000.0, "acceleration", "accel=grid", "Grid Density (M)",                  \
      "The seed's M in N_ax = floor(M * dim_ax / cbrt(V / N)) + 1: about M^3 cells per primitive")                 \
    X(uint64_t, max_cells, uint64_t(1) << 24, 1, double(uint64_t(1) << 31), "acceleration", "accel=grid",         \
      "Max Cells", "Cap on grid cells; past it the density is reduced (the grid's note says so)")                  \
    X(int, leaf_size, 8, 1, 4096, "acceleration", "accel=adaptive", "Leaf Size",                                    \
      "Adaptive grid: a cell with more primitives than this (a sphere or cone counts as 4) is refined by a grid "  \
      "of its own")                                                                                                 \
    X(int, grid_levels, 2, 0, 4, "acceleration", "accel=adaptive", "Grid Levels",                                   \
      "Adaptive grid: refining levels below the root grid (0: the root grid alone)")                               \
    X(Instancing, instancing, Instancing::Auto, 0, 0, "acceleration", "accel=adaptive", "Instancing",             \
      "Adaptive grid: trace the copies of a mesh (Geometry Nodes and particle instances) through one grid of the " \
      "mesh, placed by a grid over the copies, instead of building over every copy's triangles")                  \
    X(bool, mailboxes, true, 0, 1, "acceleration", "accel=grid", "Mailboxes",                                      \
      "Skip primitives this ray already tested (per-thread stamps)")                                               \
    X(bool, skip_empty, true, 0, 1, "acceleration", "accel!=none", "Skip Empty Space",                             \
      "Jump across blocks of empty grid cells; off walks every cell, as Havran & Sixta count them")                \
    X(int, threads, 0, 0, 1024, "performance", "", "Threads", "Worker threads, 0 = all cores")                     \
    X(int, tile_size, 32, 1, 4096, "performance", "", "Tile Size", "Tile edge in pixels")                          \
    X(uint32_t, seed, 0, 0, 4294967295.0, "performance", "", "Seed",                                               \
      "Random seed: the image is a pure function of the scene, the settings and the seed")                         \
    X(int, max_depth, 5, 1, 64, "sampling", "", "Max Depth", "Ray generations (1 = primary rays only)")            \
    X(float, min_weight, 1e-3f, 0.0, 1.0, "sampling", "", "Min Path Weight",                                       \
      "Secondary rays whose path weight falls below this are skipped")                                             \
    X(AAMode, aa, AAMode::Center, 0, 0, "sampling", "", "Anti-Aliasing", "Where a pixel's camera rays go")         \
    X(int, aa_samples, 1, 1, 64, "sampling", "aa!=center", "AA Samples (n)", "n: n x n camera samples per pixel")  \
    X(float, adaptive_threshold, 0.05f, 0.0, kNoLimit, "sampling", "aa=adaptive", "Adaptive Threshold",            \
      "Colour difference between corners that makes a square subdivide")                                          \
    X(int, adaptive_depth, 3, 0, 6, "sampling", "aa=adaptive", "Adaptive Depth", "Maximum subdivision levels")    \
    X(PixelFilter, filter, PixelFilter::Box, 0, 0, "sampling", "", "Pixel Filter", "How samples are weighted")     \
    X(float, filter_width, 0.5f, 0.01, 4.0, "sampling", "filter=gaussian", "Filter Width",                         \
      "Gaussian standard deviation in pixels (clipped at 2 sigma)")                                                \
    X(ShadowMode, shadow, ShadowMode::Hard, 0, 0, "lights", "", "Soft Shadows", "Where shadow rays go on a light") \
    X(int, shadow_samples, 1, 1, 64, "lights", "shadow!=hard", "Shadow Samples",                                   \
      "random: rays per light; area: n of the n x n light grid (finer for more pixel samples)")                   \
    X(bool, world_shadows, false, 0, 1, "lights", "", "World Shadows",                                             \
      "The scene blocks the world's light (ambient colour, environment): shadow rays toward the world, as many "   \
      "as a light with a size gets")                                                                              \
    X(int, dof_samples, 1, 1, 4096, "lens", "", "DoF Samples",                                                     \
      "Lens samples per camera sample (used when the camera has an aperture)")                                     \
    X(int, glossy_samples, 1, 1, 4096, "lens", "", "Glossy Samples", "Rays at the first glossy bounce")            \
    X(Region, region, Region(), 0, 0, "host", "", "Region",                                                        \
      "(x, y, w, h) in pixels, row 0 at the top: render only this part of the image (Blender: the render border)") \
    X(int, matte_ranks, 0, 0, 16, "host", "", "Matte Ranks",                                                       \
      "Per pixel, the matte keys (Scene(matte_keys=...)) covering most of it, with their coverage, most first: "  \
      "RenderJob.matte_keys / matte_coverage, what Cryptomatte passes are made of; 0 = none (Blender: the "       \
      "view layer's Cryptomatte Levels)")

// Where a host (the Blender add-on) starts from other defaults, and why.
// X(name, default as the host writes it, reason)
#define GW_HOST_DEFAULTS(X)                                                                              \
    X(aa, "jittered", "A final render in Blender is expected to be anti-aliased; the library keeps the "  \
                      "seed's single centre ray, the baseline its tables compare against")               \
    X(aa_samples, "2", "2 x 2 jittered samples: anti-aliased at 4x the cost of one ray")                 \
    X(shadow, "area", "Blender's lights have a size (point and spot radius, sun angle, area size) and "  \
                      "Cycles and EEVEE render their soft shadows; the library keeps the seed's hard "  \
                      "shadows, the baseline its tables compare against")                                \
    X(shadow_samples, "2", "The light's 2 x 2 strata, one per pixel sample of the 2 x 2 anti-aliasing: " \
                           "soft shadows for one shadow ray per light and hit, the cost of hard ones")   \
    X(world_shadows, "true", "Cycles' world light is blocked by the scene (contact shadows, dark "        \
                             "interiors); the library keeps Whitted's unoccluded ambient term")

#define GW_SETTING_FIELD(type, name, def, lo, hi, group, when, label, help) type name = def;
struct RenderSettings {
    GW_RENDER_SETTINGS(GW_SETTING_FIELD)
};
#undef GW_SETTING_FIELD

// Throws std::invalid_argument naming the first setting outside its limits.
void validate_settings(const RenderSettings& s);

}  // namespace gw
