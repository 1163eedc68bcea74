// Reading and writing meshes: OBJ, PLY, STL, OFF through OpenMesh; glTF binary
// (.glb) through tinygltf.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/params.h"
#include "core/progress.h"

namespace cm {

/// Reads a triangle mesh; polygons are fan-triangulated. Throws cm::Error naming the file.
Mesh read_mesh(const std::filesystem::path& file);

struct MeshWriteOptions {
    bool binary;      ///< PLY and STL: binary when true
    bool normals;     ///< write per-vertex normals where the format can hold them
    std::string name; ///< object name where the format holds one (glTF, OBJ); empty: the file's stem
    /// OBJ of a mesh with UVs and a texture: the material library and the texture image are
    /// written to these files and named in the OBJ and MTL by these names (the final names
    /// when the files are written under temporary ones). Empty: `<stem>.mtl` and
    /// `<stem>_basecolor.png` beside the OBJ.
    std::filesystem::path mtl_file, texture_file;
    std::string mtl_name, texture_name;

    MeshWriteOptions() { set_declared_defaults(*this); }
    /// `binary` and `normals` (mesh.write's parameters of the format).
    void declare(ParamBinder& b);
};

/// The names write_mesh() gives an OBJ's material library and texture: `<stem>.mtl`,
/// `<stem>_basecolor.png`, beside `obj`.
std::filesystem::path obj_material_path(const std::filesystem::path& obj);
std::filesystem::path obj_texture_path(const std::filesystem::path& obj);
/// True when write_mesh() gives an OBJ of `mesh` a material library and a texture (the
/// mesh has UVs and a texture).
bool obj_has_material(const Mesh& mesh);

/// Writes by extension: .obj .ply .stl .off .glb. Colours (Mesh::colors, linear) go into
/// PLY as 8-bit sRGB vertex colours and into glTF; UVs and the texture into glTF and OBJ
/// (+ MTL + PNG). Writes exactly to `file` (callers
/// that need atomicity write to a temporary name and rename). `progress` reports per chunk
/// of elements or bytes; a stop it throws (cm::Cancelled) leaves a partial file for the
/// caller (who wrote to a temporary name) to remove.
void write_mesh(const Mesh& mesh, const std::filesystem::path& file, const MeshWriteOptions& opt = {},
                Progress progress = {});

/// The extensions write_mesh() handles, in lower case: .obj .ply .stl .off .glb.
const std::vector<std::string>& mesh_extensions();
/// True for those extensions, in any case.
bool mesh_format_supported(const std::filesystem::path& file);

} // namespace cm
