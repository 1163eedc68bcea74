// Reading and writing meshes: OBJ, PLY, STL, OFF through OpenMesh; glTF binary
// (.glb) through tinygltf; USD (.usda, .usdz) written by io/usd_io.h.
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
    std::string name; ///< object name where the format holds one (glTF, OBJ, USD); empty: the file's stem
    /// OBJ of a mesh with UVs and a texture: the material library and the texture image are
    /// written to these files and named in the OBJ and MTL by these names (the final names
    /// when the files are written under temporary ones); a .usda's texture likewise. Empty:
    /// the names of mesh_side_files() beside the file.
    std::filesystem::path mtl_file, texture_file;
    std::string mtl_name, texture_name;

    MeshWriteOptions() { set_declared_defaults(*this); }
    /// `binary` and `normals` (mesh.write's parameters of the format).
    void declare(ParamBinder& b);
};

/// True when the mesh has UVs and a texture they address: write_mesh() then writes the
/// texture too (into a .glb or .usdz, beside an .obj or .usda).
bool has_texture_map(const Mesh& mesh);

/// The files write_mesh() writes beside `file` for `mesh`, under their default names: an
/// OBJ's material library `<stem>.mtl` and texture `<stem>_basecolor.png`, a .usda's texture
/// (the same name); empty paths for the files it does not write.
struct MeshSideFiles {
    std::filesystem::path material, texture;
};
MeshSideFiles mesh_side_files(const std::filesystem::path& file, const Mesh& mesh);

/// Writes by extension: .obj .ply .stl .off .glb .usda .usdz. Colours (Mesh::colors, linear)
/// go into PLY as 8-bit sRGB vertex colours and into glTF and USD; UVs and the texture into
/// glTF, USD and OBJ (+ MTL + PNG). Writes exactly to `file` (callers
/// that need atomicity write to a temporary name and rename). `progress` reports per chunk
/// of elements or bytes; a stop it throws (cm::Cancelled) leaves a partial file for the
/// caller (who wrote to a temporary name) to remove.
void write_mesh(const Mesh& mesh, const std::filesystem::path& file, const MeshWriteOptions& opt = {},
                Progress progress = {});

/// The extensions write_mesh() handles, in lower case: .obj .ply .stl .off .glb .usda .usdz.
const std::vector<std::string>& mesh_extensions();
/// True for those extensions, in any case.
bool mesh_format_supported(const std::filesystem::path& file);
/// True for the extensions read_mesh() reads, in any case: those, USD aside.
bool mesh_readable(const std::filesystem::path& file);

} // namespace cm
