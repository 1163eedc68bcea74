// Reading and writing meshes: OBJ, PLY, STL, OFF through OpenMesh; glTF binary
// (.glb) through tinygltf.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace cm {

/// Reads a triangle mesh; polygons are fan-triangulated. Throws cm::Error naming the file.
Mesh read_mesh(const std::filesystem::path& file);

struct MeshWriteOptions {
    bool binary = true;  ///< PLY and STL: binary when true
    bool normals = true; ///< write per-vertex normals where the format can hold them
    std::string name;    ///< object name where the format holds one (glTF); empty: the file's stem
};

/// Writes by extension: .obj .ply .stl .off .glb. Writes exactly to `file` (callers
/// that need atomicity write to a temporary name and rename).
void write_mesh(const Mesh& mesh, const std::filesystem::path& file, const MeshWriteOptions& opt = {});

/// The extensions write_mesh() handles, in lower case: .obj .ply .stl .off .glb.
const std::vector<std::string>& mesh_extensions();
/// True for those extensions, in any case.
bool mesh_format_supported(const std::filesystem::path& file);

} // namespace cm
