// USD out: the mesh as a USD layer, as text (.usda) or as a package (.usdz: the layer and
// its texture in one uncompressed zip). conceptmesh writes both itself: Debian packages no
// USD library, and the little of USD an asset needs is plain text. The layer is what
// Omniverse's asset validator asks of an asset (upAxis, metersPerUnit, extent, no
// subdivision beside authored normals); docs/mesh.md shows one and says how it was checked.
#pragma once
#include <filesystem>
#include <string>

#include "core/mesh.h"
#include "core/progress.h"
#include "io/mesh_io.h"

namespace cm {

/// True for .usda and .usdz, in any case.
bool is_usd_file(const std::filesystem::path& file);

/// `name` as a USD prim name (letters, digits and _, not starting with a digit): every other
/// byte becomes _, and a name that starts with a digit, or is empty, gets a _ in front.
std::string usd_identifier(const std::string& name);

/// Writes `mesh` as a USD layer, by `file`'s extension: `.usda`, its text; `.usdz`, a package
/// holding the layer `<name>.usda` first and the texture `<name>_basecolor.png` (zip_store.h).
/// The layer: `defaultPrim`, `upAxis = "Y"`, `metersPerUnit = 1` (the file's units are metres,
/// as in glTF: mesh.write sizes the model with `height` or `unit_scale`), the tool and its
/// version in `customLayerData`; an Xform named usd_identifier(name) of kind "component"
/// holding the Mesh `mesh`: points, triangles (faceVertexCounts, faceVertexIndices, as
/// wound: counter-clockwise seen from outside, USD's rightHanded), `extent`,
/// `subdivisionScheme = "none"`, normals (vertex, when `wo.normals` and the mesh has them),
/// UVs as `primvars:st` (faceVarying for per-corner UVs, else vertex; v up, as USD's st:
/// not flipped), colours as `primvars:displayColor` (vertex, linear; `displayOpacity` when
/// one is not opaque); with a texture, the Material `mtl/<name>`: a UsdPreviewSurface (matte:
/// roughness 1, metallic 0) whose diffuse colour is a UsdUVTexture (sRGB, clamped) of the
/// texture read through a UsdPrimvarReader_float2 of `st`, bound with MaterialBindingAPI.
/// A `.usda`'s texture is a PNG written to `wo.texture_file` and referred to, relative to the
/// layer, as `wo.texture_name` (defaults: mesh_side_files()). `progress` reports per chunk; a
/// stop it throws leaves partial files for the caller to remove. Throws cm::Error naming a
/// file that cannot be written.
void write_usd(const Mesh& mesh, const std::filesystem::path& file, const MeshWriteOptions& wo, Progress progress = {});

} // namespace cm
