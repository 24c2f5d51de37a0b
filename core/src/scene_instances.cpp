// Scene::set_instances and Scene::part: what the instanced grid
// (instanced_grid.h) is built from.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "scene.h"

namespace gw {

void Scene::set_instances(std::vector<SceneInstance> instances) {
    const size_t nt = num_triangles();
    auto bad_instance = [](size_t i, const std::string& what) {
        throw std::invalid_argument("instances[" + std::to_string(i) + "]: " + what);
    };
    std::vector<std::pair<size_t, size_t>> ranges;   // (start, index)
    for (size_t i = 0; i < instances.size(); ++i) {
        const SceneInstance& in = instances[i];
        if (in.triangle_start > nt || in.triangle_count > nt - in.triangle_start)
            bad_instance(i, "triangles " + std::to_string(in.triangle_start) + " + " +
                                std::to_string(in.triangle_count) + " lie beyond the scene's " + std::to_string(nt));
        if (in.mesh < 0) bad_instance(i, "mesh is " + std::to_string(in.mesh) + ", not >= 0");
        for (const auto& row : in.matrix)
            for (double x : row)
                if (!std::isfinite(x)) bad_instance(i, "the matrix has a non-finite value");
        if (in.triangle_count > 0) ranges.emplace_back(in.triangle_start, i);
    }
    std::sort(ranges.begin(), ranges.end());
    for (size_t k = 1; k < ranges.size(); ++k) {
        const SceneInstance& before = instances[ranges[k - 1].second];
        if (ranges[k].first < before.triangle_start + before.triangle_count)
            bad_instance(ranges[k].second, "its triangles overlap those of instances[" +
                                               std::to_string(ranges[k - 1].second) + "]");
    }
    instances_ = std::move(instances);
}

std::shared_ptr<const Scene> Scene::part(const std::vector<uint32_t>& prims, const Vec3d& shift) const {
    const bool moved = shift.x != 0 || shift.y != 0 || shift.z != 0;
    auto move = [&](const Vec3& v) {
        return moved ? Vec3(float(double(v.x) - shift.x), float(double(v.y) - shift.y), float(double(v.z) - shift.z)) : v;
    };
    std::shared_ptr<Scene> out(new Scene(PartTag{}));
    for (size_t i = 0; i < prims.size(); ++i)
        if (prims[i] >= num_prims() || (i > 0 && prims[i] <= prims[i - 1]))
            throw std::logic_error("Scene::part: the primitives must be ascending indices of this scene");
    Bounds tri_bounds;
    for (uint32_t p : prims) {
        switch (kind_of(p)) {
        case PrimKind::Triangle:
            for (int c = 0; c < 3; ++c) {
                out->tri_verts_.push_back(move(tri_verts_[3 * size_t(p) + size_t(c)]));
                tri_bounds.grow(out->tri_verts_.back());
            }
            ++out->nt_;
            break;
        case PrimKind::Sphere:
            if (moved) throw std::logic_error("Scene::part: only triangles are moved");
            out->centers_.push_back(centers_[local_index(p)]);
            out->radii_.push_back(radii_[local_index(p)]);
            ++out->ns_;
            break;
        default:
            if (moved) throw std::logic_error("Scene::part: only triangles are moved");
            out->cones_.push_back(cones_[local_index(p)]);
            ++out->nc_;
            break;
        }
    }
    out->tri_verts_.push_back(Vec3());   // (the SIMD test's padding corner, as in the constructor)
    out->materials_.assign(1, Material());
    out->tri_mat_.assign(out->nt_, 0);
    out->sphere_mat_.assign(out->ns_, 0);
    out->cone_mat_.assign(out->nc_, 0);
    out->compute_bounds(tri_bounds);
    return out;
}

}  // namespace gw
