// The Marching Cubes case table, generated at start-up from the cube's geometry
// rather than written out, so that the ambiguous faces can be resolved per face
// at run time and both cells sharing a face always agree.
//
// Numbering (all local to one cell):
//  - corner c: bit 0 = +x, bit 1 = +y, bit 2 = +z offset from the cell origin;
//    the case index (config) has bit c set when corner c is inside.
//  - edge e = 4 * axis + (o0 | o1 << 1), with o0, o1 the offsets along the two other
//    axes in increasing axis order; it runs from corner kEdgeCorner[e] along +axis.
//  - face f = 2 * n + side: the face with normal axis n at offset side (0 low, 1 high).
//    Its four edges in canonical order are Eu0, Eu1, Ev0, Ev1 (u < v its in-plane axes;
//    Eu0 is the u-edge at v = 0, Ev1 the v-edge at u = 1, ...).
//
// On an ambiguous face (inside corners on one diagonal, outside on the other), the four
// crossings pair up in one of two ways: pairing A joins (Eu0, Ev0) and (Eu1, Ev1),
// pairing B joins (Eu0, Ev1) and (Eu1, Ev0). The pairing is a property of the face,
// chosen from data both cells see identically, so the surface is consistent across the face.
// Each case then has closed loops of crossed edges; every loop is one disc of surface.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace cm::mc {

struct EdgeDef {
    std::uint8_t axis;   ///< 0 x, 1 y, 2 z
    std::uint8_t corner; ///< start corner; the edge runs to corner | (1 << axis)
};

/// One closed loop of crossed edges: a disc of surface inside the cell.
struct Loop {
    enum Mode : std::uint8_t {
        Fan,      ///< a fan from one of the vertices in `fan_apexes` (chosen at run time)
        Fixed,    ///< the triangles in `tris` (loop-local indices)
        Centroid, ///< a fan around one extra vertex at the loop's centroid
    };
    std::uint8_t size = 0; ///< vertices (= crossed edges), 3..12
    Mode mode = Fan;
    std::uint16_t fan_apexes = 0;         ///< bit k: a fan from vertex k uses only interior diagonals
    std::uint8_t tri_count = 0;           ///< Fixed only
    std::array<std::uint8_t, 12> edges{}; ///< in order; the loop's orientation is outward
    std::array<std::array<std::uint8_t, 3>, 10> tris{};
};

struct Case {
    std::uint32_t first_loop = 0;
    std::uint8_t loop_count = 0;
    bool valid = false;
};

class Table {
public:
    static const Table& get();

    /// Bit f set when face f of `config` is ambiguous.
    std::uint8_t ambiguous_faces(unsigned config) const { return ambiguous_[config]; }
    /// Face bits (bit f: pairing B on face f) that separate the inside corners on every
    /// ambiguous face (inside 6-connected): the tie-break and the `separate` rule.
    std::uint8_t separating_bits(unsigned config) const { return separating_[config]; }
    /// The case for `config` with pairings `face_bits` (bits of non-ambiguous faces ignored).
    const Case& lookup(unsigned config, unsigned face_bits) const {
        return cases_[config | ((face_bits & ambiguous_[config]) << 8)];
    }
    const Loop& loop(std::uint32_t i) const { return loops_[i]; }

    struct Stats {
        std::size_t cases = 0, loops = 0, fan = 0, fixed = 0, centroid = 0, max_loop = 0;
    };
    Stats stats() const;

private:
    Table();
    std::array<std::uint8_t, 256> ambiguous_{};
    std::array<std::uint8_t, 256> separating_{};
    std::vector<Case> cases_; ///< 256 * 64, indexed by config | face_bits << 8
    std::vector<Loop> loops_;
};

extern const std::array<EdgeDef, 12> kEdges;
/// Edges of face f in canonical order Eu0, Eu1, Ev0, Ev1.
extern const std::array<std::array<std::uint8_t, 4>, 6> kFaceEdges;

} // namespace cm::mc
