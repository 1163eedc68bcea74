// The hidden-depth prior of hull.plausible (`ghost`; plausible_ghost.h). At each station along
// a grid axis a, the hull's section is a union of boxes, each pairing a run along b (from the
// hull's projection along c) with a run along c (from the projection along b). Where a run T
// along one of them is thin against the run D along the other, and D is the depth of another,
// wider part at the same station (a run T' on the same line of the projection along D's axis,
// about as wide as D, whose box the view along a covers), the thin part's depth is hidden behind
// the wider one: D is that part's, not the thin one's. The thin part then gets a round section
// as deep as it is wide, centred where the view along a puts it (the middle of that view's run
// through the voxel, within D).
#include "plausible_ghost.h"

#include "plausible_projection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace cm::plausible {

namespace {

// A thin run: at most kThinLow of the depth has the whole say, from kThinHigh on none.
constexpr double kThinLow = 0.3, kThinHigh = 0.45;
// The wider part: its run along the thin one's axis at least this share of the depth (a smooth
// step), and the view along the slicing axis showing it over at least this share of the depth.
constexpr double kWideLow = 0.5, kWideHigh = 0.7;
constexpr double kSpanLow = 0.7, kSpanHigh = 0.9;

// How clearly the depth D of a thin run T across axis a is another part's, for a station, T
// and D: the voxels of a leaf share a few per station.
struct Hidden {
    int station = std::numeric_limits<int>::min();
    Interval T, D, O; ///< O: the wider part's run along T's axis
    double weight = 0.0;
};
// Per axis a and thin axis (b or c), the last answers per station modulo 8, one thread's.
using HiddenMemo = std::array<std::array<std::array<Hidden, 8>, 2>, 3>;

// The share of the depth D the part over O spans in the projection A (along the slicing axis):
// the positions along D where A has an inside pixel within O.
double span(const Projection& A, int t, const Interval& O, const Interval& D) {
    int hit = 0;
    for (int x = D.lo; x <= D.hi; ++x) hit += (t == A.u ? A.count(O.lo, O.hi, x, x) : A.count(x, x, O.lo, O.hi)) > 0;
    return double(hit) / double(D.size());
}

class GhostFinder {
public:
    explicit GhostFinder(const std::array<Projection, 3>& proj) : proj_(proj) {}

    GhostValue value(const Coord& p, HiddenMemo& memo) const {
        GhostValue best;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int side = 0; side < 2; ++side) {
                const int t = side == 0 ? b : c, d = side == 0 ? c : b;
                // T along t from the projection along d, D along d from the one along t.
                const Interval T = proj_[std::size_t(d)].run(t, p), D = proj_[std::size_t(t)].run(d, p);
                if (T.empty() || D.empty() || double(T.size()) >= kThinHigh * double(D.size())) continue;
                const Hidden& h0 = hidden(a, side, t, d, p, T, D, memo);
                const double w = h0.weight;
                if (w <= best.weight) continue;
                // Hidden here: the wider part lies at this voxel's depth, in front of or
                // behind it along t (a plate reaching beyond it is not hidden there).
                if (!behind(a, t, d, p, h0.O)) continue;
                // The part's place along d: the view along a's run through p, within D.
                const Interval R = proj_[std::size_t(a)].run(d, p);
                const Interval in{std::max(R.lo, D.lo), std::min(R.hi, D.hi)};
                const Place at = place(a, t, h0.O, T, D, in);
                const double ut = std::abs(double(p[t]) - T.mid()) / T.half();
                const double ud = std::abs(double(p[d]) - at.mid) / at.half;
                best.weight = float(w);
                best.field = float((std::sqrt(ut * ut + ud * ud) - 1.0) * std::min(T.half(), at.half));
            }
        }
        return best;
    }

private:
    // The hidden part's section along d: centre and half depth.
    struct Place {
        double mid, half;
    };
    // Round, as deep as the part is wide, in the middle of `in` (the view along a's run through
    // the voxel, within D): unless part of `in` lies beyond the wider part's depth (no pixel of
    // the view along a within O there). The depth D reaches there, and no other part at this
    // station can give it but the thin one: its section is moved (and deepened if need be) to
    // take that stretch in, so the covering of the lines of sight does not have to swell the
    // section back into a plate as deep as D. A stretch on both sides of the wider part (less
    // than half of its extent beyond the part) leaves the section in the middle.
    Place place(int a, int t, const Interval& O, const Interval& T, const Interval& D, const Interval& in) const {
        if (in.empty()) return {D.mid(), T.half()};
        const double h = std::min(T.half(), in.half());
        Place at{in.mid(), h};
        if (O.empty()) return at;
        const Projection& A = proj_[std::size_t(a)];
        Interval U;
        int n = 0;
        for (int x = in.lo; x <= in.hi; ++x) {
            if ((t == A.u ? A.count(O.lo, O.hi, x, x) : A.count(x, x, O.lo, O.hi)) > 0) continue;
            if (U.empty()) U.lo = x;
            U.hi = x;
            ++n;
        }
        if (U.empty() || U.size() == in.size() || 2 * n < U.size()) return at;
        if (U.half() >= h) return {U.mid(), U.half()};
        // The least move from the middle that takes U in.
        at.mid = std::clamp(at.mid, double(U.hi) + 0.5 - h, double(U.lo) - 0.5 + h);
        return at;
    }
    bool behind(int a, int t, int d, const Coord& p, const Interval& O) const {
        const Projection& A = proj_[std::size_t(a)];
        return (t == A.u ? A.count(O.lo, O.hi, p[d], p[d]) : A.count(p[d], p[d], O.lo, O.hi)) > 0;
    }
    const Hidden& hidden(int a, int side, int t, int d, const Coord& p, const Interval& T, const Interval& D,
                         HiddenMemo& memo) const {
        Hidden& slot = memo[std::size_t(a)][std::size_t(side)][std::size_t(p[a] & 7)];
        if (slot.station == p[a] && slot.T.lo == T.lo && slot.T.hi == T.hi && slot.D.lo == D.lo && slot.D.hi == D.hi)
            return slot;
        const double thin = 1.0 - smoothstep(double(T.size()) / double(D.size()), kThinLow, kThinHigh);
        double wide = 0.0;
        Interval best;
        // The other runs along t on the line of the projection along d at this station.
        const Projection& P = proj_[std::size_t(d)];
        const Projection& A = proj_[std::size_t(a)];
        const int first = t == P.u ? P.u0 : P.v0, end = first + (t == P.u ? P.nu : P.nv);
        Coord q = p;
        for (int x = first; x < end;) {
            q[t] = x;
            const Interval O = P.run(t, q);
            if (O.empty()) {
                ++x;
                continue;
            }
            x = O.hi + 1;
            if (O.lo == T.lo) continue;
            const double share = smoothstep(double(O.size()) / double(D.size()), kWideLow, kWideHigh);
            if (share <= wide) continue;
            const double w = share * smoothstep(span(A, t, O, D), kSpanLow, kSpanHigh);
            if (w > wide) wide = w, best = O;
        }
        slot = {p[a], T, D, best, thin * wide};
        return slot;
    }

    const std::array<Projection, 3>& proj_;
};

} // namespace

void ghost_by_leaf(const HullVoxels& vox, const std::array<Projection, 3>& proj, const std::vector<LeafMask>* only,
                   const GhostLeafBody& body) {
    const GhostFinder finder(proj);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::uint32_t> index;
        std::vector<GhostValue> values;
        index.reserve(LeafT::SIZE);
        values.reserve(LeafT::SIZE);
        HiddenMemo memo;
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const LeafT& leaf = vox.leaves.leaf(l);
            index.clear();
            values.clear();
            vox.for_leaf(l, only ? &(*only)[l] : nullptr, [&](std::size_t i, openvdb::Index o) {
                index.push_back(std::uint32_t(i));
                values.push_back(finder.value(leaf.offsetToGlobalCoord(o), memo));
            });
            body(index.data(), values.data(), values.size());
        }
    });
}

} // namespace cm::plausible

namespace cm::plausible {

// The hidden-depth prior raises the field (never lowers it) by its weight times `ghost`, where
// the round section it gives a hidden part ends; a square section keeps the hull. On grids finer
// than 256 it is taken where the views' fields are (fill_in() interpolates the result).
void Plausible::ghost() {
    const float share = float(opt_.ghost);
    const bool coarse = coarse_ != nullptr;
    std::atomic<std::size_t> hidden{0};
    ghost_by_leaf(vox_, projections(), coarse ? &coarse_->exact() : nullptr,
                  [&](const std::uint32_t* index, const GhostValue* values, std::size_t cnt) {
                      std::size_t n = 0;
                      for (std::size_t k = 0; k < cnt; ++k) {
                          if (thin_[index[k]] & kSquare) continue;
                          const float w = share * values[k].weight;
                          if (w <= 0.0f) continue;
                          float& phi = phi_[index[k]];
                          phi += w * std::max(0.0f, values[k].field - phi);
                          n += w >= 0.5f && values[k].field > 0.0f;
                      }
                      hidden += n;
                  });
    st_.ghost_voxels = hidden;
}

} // namespace cm::plausible
