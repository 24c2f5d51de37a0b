// Tangents for normal maps: per triangle corner, the UV tangent dp/du
// averaged over the corners that share the vertex, its UV and the
// orientation of the UV map there (as MikkTSpace, which Blender and Cycles
// use, averages), made orthogonal to the vertex normal, with the sign that
// gives the bitangent (n x T, or its opposite where the UVs are mirrored).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>


namespace gw {

// 4 floats per corner (12 per triangle): tangent x, y, z and the bitangent's
// sign (+1 or -1; 0 with a zero tangent where no corner of the group has UVs
// of any area), for the nt triangles tris (3 vertex indices each) of verts
// (x, y, z per vertex), normals (per vertex, or null: face normals) and uvs
// (6 per triangle). Corners are grouped by position, normal and UV, not by
// vertex index, so a range of a scene's triangles (one instance) gives its
// own tangents.
std::vector<float> corner_tangents(const float* verts, const int32_t* tris, size_t nt, const float* normals,
                                   const float* uvs);

}  // namespace gw
