// Tangents for normal maps: per triangle corner, the UV tangent dp/du
// averaged over the corners that share the vertex, its UV and the
// orientation of the UV map there (as MikkTSpace, which Blender and Cycles
// use, averages), made orthogonal to the vertex normal, with the sign that
// gives the bitangent (n x T, or its opposite where the UVs are mirrored).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "buffer_pool.h"

namespace gw {

// 4 floats per corner (12 per triangle): tangent x, y, z and the bitangent's
// sign (+1 or -1; 0 with a zero tangent where no corner of the group has UVs
// of any area). verts (x, y, z per vertex), tris (3 vertex indices per
// triangle), normals (per vertex, or empty: face normals), uvs (6 per triangle).
std::vector<float> corner_tangents(const PooledVector<float>& verts, const PooledVector<int32_t>& tris,
                                   const PooledVector<float>& normals, const PooledVector<float>& uvs);

}  // namespace gw
