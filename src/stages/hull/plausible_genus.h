// The kept volume of hull.plausible with no handle the hull has not: a removal that would
// open a tunnel through what is kept (or seal a cavity in it) is taken back.
//
// The field removes every voxel where it is above 0, all at once. Where two removed regions
// come close from two sides of a thin part (an ear's base, the gap between an arm and the
// body), they can meet: the kept volume gets a through-hole the drawings never showed. The
// removed voxels are taken out again one at a time from the hull, the most removable (highest
// field) first, each only while its 3x3x3 neighbourhood says its removal leaves the outside
// one piece there (a voxel whose removed neighbours would be joined by it into one passage
// around kept voxels closes a loop of the outside: a tunnel, or, with none, a cavity); what
// still waits at the end stays, a wall where the field is lowest. Cutting a part off stays
// allowed (the outside about the cut is one piece); cutting a ring of the hull through does
// not (the first voxel of the cut's last layer would join the outside to itself). Then no two
// kept voxels touch by an edge or a corner alone across a voxel taken out, where putting it
// back seals no pocket of the outside and joins no two kept voxels apart about it (which would
// close a loop): it comes back, so Marching Cubes, whichever way it
// resolves such a face, gives the surface the topology of the voxels (a diagonal contact read
// as apart opens a hole between two concavities).
#pragma once
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "leaf_masks.h"

namespace cm::plausible {

/// The field at a voxel of the hull: its leaf (LeafManager order) and offset in the leaf.
using VoxelField = std::function<float(std::size_t, openvdb::Index)>;

/// Puts back into `kept` (the hull's voxelized leaves, `leaves`, as the removal left them)
/// the removed voxels (on in `hull`, per leaf in LeafManager order, off now) whose removal
/// would open a tunnel or seal a cavity, as above, `field` giving each voxel's removal order
/// (highest first). Only what needs it goes one voxel at a time: a 26-connected piece (or a
/// chunk of one, split at its median field) goes at once when its removal leaves the Euler
/// characteristic unchanged, the kept voxels about it are one piece, each of its voxels
/// reaches the outside by face steps within it and the outside voxels about it that touch
/// it by a face are one 6-connected piece among the outside voxels about it (so no tunnel,
/// part cut off or cavity hides in the sum, and no tunnel opened is traded for a handle of
/// the hull cut). Then closes the diagonal contacts the removal made where the voxel put back
/// changes no topology (kept_one_piece(), removal_keeps_outside()). Returns the number of
/// voxels put back.
std::size_t keep_hull_genus(openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<LeafMask>& hull,
                            const VoxelField& field);

/// Whether removing the centre of a 3x3x3 neighbourhood (`nb`, bit x + 3 y + 9 z, 1 inside;
/// the centre bit 13 ignored) leaves the outside in one piece there: its outside voxels among
/// the 18 nearest, 6-connected within them, form exactly one piece that touches a face of the
/// centre.
bool removal_keeps_outside(unsigned nb);

/// Whether the on voxels of a neighbourhood (`nb` as above; the centre ignored) are one
/// 26-connected piece within it: putting the centre back then joins nothing that was apart
/// there (with removal_keeps_outside(), the centre is simple: it changes no topology).
bool kept_one_piece(unsigned nb);

/// The 26-connected pieces of the on voxels of a neighbourhood (`nb` as above; the centre
/// ignored) within it: their masks in `piece`, and how many.
int kept_pieces(unsigned nb, std::array<unsigned, 26>& piece);

/// Whether the centre of a neighbourhood (`nb` as above), taken out, stands between two on
/// voxels that touch by an edge or a corner alone: a 2x2 square through the centre whose on
/// voxels are diagonal, or a 2x2x2 cube with two opposite corners on and its six others off.
bool diagonal_contact(unsigned nb);

/// The change of the Euler characteristic (V - E + F - C of the union of closed voxel cubes)
/// of the kept volume that taking out the centre of a neighbourhood causes in the lattice
/// cells of the centre no earlier voxel (lower bit) of `gone` touches: `kept` the kept
/// voxels about it, `gone` those taken out with it (26-connected to it; its own bit 13 on).
/// Summed over every voxel of a 26-connected set taken out at once, the change its removal
/// causes (sets with no voxel within one of each other touch no cell in common).
int euler_change(unsigned kept, unsigned gone);

} // namespace cm::plausible
