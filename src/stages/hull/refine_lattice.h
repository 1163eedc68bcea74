// The lattice of hull.marching_intersections and what its two searches share: the crossings
// of edges whose ends differ in occupancy (refine.cpp) and the thin parts between two outside
// ends (refine_thin.cpp).
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/vec.h"
#include "geometry/visual_hull.h"

namespace cm::refining {

using Coord = openvdb::Coord;
using OccAccessor = openvdb::tree::ValueAccessor<const openvdb::BoolTree>;
constexpr int kDim = 8;
inline const openvdb::Vec3f kUnset(-1.f, -1.f, -1.f);

// The world position of lattice (grid index) points.
struct Lattice {
    Vec3d origin;
    double h = 1;
    Vec3d at(const Coord& c) const { return {origin.x + h * c.x(), origin.y + h * c.y(), origin.z + h * c.z()}; }
};

// What the views seen along a world axis (orthographic, drop axis d) said about the edges of
// 8^3 blocks. Such a view sees every edge along one line of the d axis alike (its projection
// ignores the d coordinate exactly), and on the part of the hull that view carves (a cone
// extruded along d) the edges of a line cross it alike too: the view's class, start and flips
// for a line are found once and given again to the line's other edges, in the block and in
// the blocks after it along d (a thread takes the blocks in order). Answers are those of the
// view itself, so the crossings are the same.
class LineAnswers {
public:
    explicit LineAnswers(const VisualHull& hull) : hull_(hull), slot_(hull.size(), -1) {
        for (std::size_t i = 0; i < hull.size() && i < 64 && kept_ < kViews; ++i)
            if (const int d = hull.field(i).drop_axis(); d >= 0) {
                drop_[kept_] = d;
                slot_[i] = kept_++;
            }
    }
    // The block at `o` comes next: a view keeps its answers when the block lies on the same
    // lines as the last one (the next block along the view's axis), and forgets them otherwise.
    void new_block(const Coord& o) {
        for (int s = 0; s < kept_; ++s) {
            const int d = drop_[s], u = (d + 1) % 3, w = (d + 2) % 3;
            if (has_[s] && at_[s][0] == o[u] && at_[s][1] == o[w]) continue;
            std::fill_n(known_ + s * kPerView, kPerView, std::uint8_t(0));
            has_[s] = true;
            at_[s][0] = o[u];
            at_[s][1] = o[w];
        }
    }

    // The views' answers about the edge from `p` (the block's local coordinates, 0 to 7) along
    // axis `a`, whose ends are the world points `wa` and `wb`.
    class Edge {
    public:
        Edge(LineAnswers& cache, const Coord& p, int a, const Vec3d& wa, const Vec3d& wb)
            : c_(cache), p_(p), a_(a), wa_(wa), wb_(wb) {}
        SilhouetteField::Class classify(std::size_t i) const {
            const int k = entry(i);
            if (k < 0) return c_.hull_.field(i).classify_segment(wa_, wb_);
            if (!(c_.known_[k] & kClass)) {
                c_.class_[k] = static_cast<signed char>(c_.hull_.field(i).classify_segment(wa_, wb_));
                c_.known_[k] |= kClass;
            }
            return static_cast<SilhouetteField::Class>(c_.class_[k]);
        }
        int transitions(std::size_t i, bool& st, double* out, int max) const {
            const int k = entry(i);
            if (k >= 0 && (c_.known_[k] & kFlips) && c_.count_[k] < max) {
                st = c_.start_[k] != 0;
                std::copy_n(c_.flips_[k], c_.count_[k], out);
                return c_.count_[k];
            }
            const int n = c_.hull_.field(i).transitions(wa_, wb_, st, out, max);
            if (k >= 0 && n <= kKeep && n < max) {
                c_.start_[k] = st;
                c_.count_[k] = static_cast<std::uint8_t>(n);
                std::copy_n(out, n, c_.flips_[k]);
                c_.known_[k] |= kFlips;
            }
            return n;
        }

    private:
        // The entry of view i's line through the edge, or -1 for a view asked every time.
        int entry(std::size_t i) const {
            const int s = c_.slot_[i];
            if (s < 0) return -1;
            const int d = c_.drop_[s];
            return ((s * 3 + a_) * 8 + p_[(d + 1) % 3]) * 8 + p_[(d + 2) % 3];
        }
        LineAnswers& c_;
        const Coord p_;
        const int a_;
        const Vec3d &wa_, &wb_;
    };

private:
    static constexpr int kViews = 8; ///< views kept per block (more are asked every time)
    static constexpr int kKeep = 6;  ///< flips kept per line (a line with more is asked again)
    static constexpr int kPerView = 3 * 64;
    static constexpr int kEntries = kViews * kPerView;
    static constexpr std::uint8_t kClass = 1, kFlips = 2;
    const VisualHull& hull_;
    std::vector<int> slot_; ///< per view: its place among the kept views, or -1
    int kept_ = 0;
    int drop_[kViews] = {};
    bool has_[kViews] = {};  ///< whether the view's entries are of some block's lines
    int at_[kViews][2] = {}; ///< those lines' block coordinates
    std::uint8_t known_[kEntries];
    signed char class_[kEntries];
    std::uint8_t start_[kEntries], count_[kEntries];
    double flips_[kEntries][kKeep];
};

} // namespace cm::refining
