// Flat caps: faces whose three corners lie on one line (a corner in the middle of the
// opposite edge: zero area, or so little that rounding to a file's precision or a scale to
// metres makes it zero). They cover nothing, but a closed mesh can hold them where a row of
// vertices lies on a straight crease; an importer or a renderer takes them for broken faces.
// Flipping the cap's long edge with the face across it removes the cap and leaves the
// surface as it was: the two new faces cover what the two old ones did.
#pragma once
#include <cstddef>

#include "core/mesh.h"

namespace cm {

/// What flip_flat_caps() did.
struct FlatCaps {
    std::size_t found = 0;   ///< flat caps in the mesh before
    std::size_t flipped = 0; ///< edges flipped
    std::size_t left = 0;    ///< caps no flip could remove (a seam of the texture, an edge already there)
};

/// @brief The flatness under which a face is a cap: the distance of its middle corner from
/// its longest edge, against that edge's length.
inline constexpr double kFlatCapHeight = 1e-5;

/// @brief Removes the flat caps of `mesh` (a face whose middle corner lies within
/// `kFlatCapHeight` of its longest edge's length from that edge) by flipping that edge with
/// the face across it, when the flip gives two faces that are not flat, turned the same way
/// as before, an edge not already in the mesh, and (with corner UVs) does not cross a seam of
/// the texture. Positions, UVs, normals and colours are left as they are; the faces' count
/// too. Faces repeating a vertex are not caps (they are left for the mesh check to name).
FlatCaps flip_flat_caps(Mesh& mesh);

/// @brief How many faces of `mesh` are flat caps (as flip_flat_caps() finds them).
std::size_t count_flat_caps(const Mesh& mesh);

} // namespace cm
