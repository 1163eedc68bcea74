// glTF binary (.glb) through tinygltf; used by read_mesh()/write_mesh() (mesh_io.h).
#pragma once
#include <filesystem>
#include <string>

#include "core/mesh.h"
#include "core/progress.h"

namespace cm {

/// One mesh, one triangle primitive: POSITION (with min/max), NORMAL when asked and
/// present, TEXCOORD_0 (v flipped: Mesh UVs have v up, as OBJ; glTF has v down),
/// COLOR_0, and 32-bit indices. Throws cm::Error naming the file.
/// The mesh and its node are called `name` (the file's stem when empty). `progress` reports
/// per chunk and may throw to stop (see write_mesh()).
void write_glb(const Mesh& mesh, const std::filesystem::path& file, bool normals, const std::string& name = {},
               Progress progress = {});

/// Every triangle primitive of the default scene (or of all meshes when there is no
/// scene), with node transforms applied, merged into one mesh. Throws cm::Error.
Mesh read_glb(const std::filesystem::path& file);

} // namespace cm
