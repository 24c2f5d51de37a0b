// Per-render settings (mirrored by gridwalk.RenderSettings in Python).
#pragma once
#include <cstdint>

namespace gw {

enum class AAMode : int { Center = 0, Jittered = 1, Random = 2, Adaptive = 3, Sobol = 4 };
enum class ShadowMode : int { Hard = 0, Random = 1, Area = 2 };
enum class PixelFilter : int { Box = 0, Gaussian = 1 };

struct RenderSettings {
    int accel = 1;                     // 0 = none (brute force), 1 = uniform grid
    double grid_density = 2.0;         // the seed's M
    uint64_t max_cells = 1ull << 24;   // grid cell cap (M is reduced past it)
    bool mailboxes = true;
    bool skip_empty = true;            // grid: jump across blocks of empty cells
    int threads = 0;                   // 0 = all cores
    int tile_size = 32;
    int max_depth = 5;                 // ray generations: primary = 1
    uint32_t seed = 0;
    AAMode aa = AAMode::Center;
    int aa_samples = 1;                // n: n x n samples per pixel (jittered/random/sobol)
    float adaptive_threshold = 0.05f;  // colour difference that triggers subdivision
    int adaptive_depth = 3;            // maximum subdivision levels
    PixelFilter filter = PixelFilter::Box;
    float filter_width = 0.5f;         // Gaussian standard deviation in pixels (clipped at 2 sigma)
    ShadowMode shadow = ShadowMode::Hard;
    int shadow_samples = 1;            // random: rays per light; area: n for the n x n light grid
    int dof_samples = 1;               // lens samples per pixel sample
    int glossy_samples = 1;            // rays at the first glossy bounce
    float min_weight = 1e-3f;          // skip secondary rays whose path weight is below this
    int region[4] = {0, 0, 0, 0};      // x, y, w, h of the part to render; w = 0: whole image
};

}  // namespace gw
