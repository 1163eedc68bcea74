// The lofted prior of hull.plausible (prior: loft; plausible_loft.h). A modeller lofting from
// blueprints sweeps a cross-section along the object, scaled at each station to the extents
// the other views give, rounded where the drawings show curves and kept square where they
// show straight walls meeting at corners. Here the "drawings" are the hull's projections along
// the grid's three axes (for the named views front/right/top they are the drawings
// themselves, at the grid's pitch), so the prior needs no view to lie along an axis and takes
// any set of views.
#include "plausible_loft.h"

#include "plausible_projection.h"
#include "plausible_tracks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace cm::plausible {

namespace {

// Exponent of a section where the walls are straight along the slicing axis and the view
// along it confirms the box's sides: a superellipse this square is the box to a few
// hundredths of its half-width, so the hull decides the section.
constexpr double kSquare = 32.0;
// The share of a section's box the view along its axis must cover for the lofted section to
// count (a smooth step between the two; an inscribed ellipse covers 0.785).
constexpr double kFitLow = 0.5, kFitHigh = 0.7;

double jaccard(const Interval& a, const Interval& b) {
    if (a.empty() || b.empty()) return 0.0;
    const int i = std::min(a.hi, b.hi) - std::max(a.lo, b.lo) + 1;
    const int u = std::max(a.hi, b.hi) - std::min(a.lo, b.lo) + 1;
    return i > 0 ? double(i) / double(u) : 0.0;
}

// What a section's box across axis a at station p[a] gives whatever p's other coordinates:
// whether the view along a shows the box's four sides as its outline, and how well it covers
// the box (Lofter::fit). The voxels of a leaf share a few boxes per station.
struct BoxFacts {
    int station = std::numeric_limits<int>::min();
    Interval ib, ic;
    bool sides = false;
    double fit = 0.0;
};

/// The last box facts per axis and station (modulo a leaf's side) of one thread's voxels.
using BoxMemo = std::array<std::array<BoxFacts, 8>, 3>;

class Lofter {
public:
    Lofter(const std::array<Projection, 3>& proj, int maxdim, double round_exponent)
        : round_(round_exponent), proj_(proj), pairs_(proj_, maxdim) {}

    // The field at grid point p (cells; <= 0 inside the lofted section) and how square the
    // section taken there is; `found` false where no axis has a section through p (p projects
    // outside the hull along two axes).
    // `memo` (optional, one thread's) keeps what the boxes of voxels just taken gave.
    LoftValue value(const Coord& p, bool* found = nullptr, BoxMemo* memo = nullptr) const {
        double best_key = 1e300, square = 0.0, fitted = 0.0;
        Interval sb, sc;
        int best_a = -1;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            // The section's box: along b from the projection along c, along c from the one along b.
            const Interval ib = run(c, b, p), ic = run(b, c, p);
            if (ib.empty() || ic.empty()) continue;
            const BoxFacts facts = box_facts(a, b, c, p, ib, ic, memo);
            const double w = facts.sides ? squareness(a, b, c, p, ib, ic) : 0.0;
            const double f = facts.fit;
            // Sections the view along their axis does not confirm count larger (up to 3x).
            const double key = ib.half() * ic.half() * (1.0 - 0.9 * w) * (3.0 - 2.0 * std::max(f, w));
            if (key >= best_key) continue;
            best_key = key;
            square = w;
            fitted = std::max(f, w);
            best_a = a;
            sb = ib;
            sc = ic;
        }
        if (found) *found = best_a >= 0;
        if (best_a < 0) return {};
        const int b = (best_a + 1) % 3, c = (best_a + 2) % 3;
        // In a box pairing two parts' runs that the evidence rules out, across any axis
        // (plausible_tracks.h): outside (about the cells to the nearest side of the section's
        // box, at least 1) with the whole say.
        if (pairs_.dropped(0, p) || pairs_.dropped(1, p) || pairs_.dropped(2, p)) {
            const int d = std::min({p[b] - sb.lo, sb.hi - p[b], p[c] - sc.lo, sc.hi - p[c]});
            return {float(d + 1), 0.0f, 1.0f, 1.0f};
        }
        const double hb = sb.half(), hc = sc.half();
        const double ub = std::abs(double(p[b]) - sb.mid()) / hb, uc = std::abs(double(p[c]) - sc.mid()) / hc;
        double s;
        if (square == 0.0 && round_ == 2.0) {
            s = std::sqrt(ub * ub + uc * uc);
        } else {
            const double e = round_ * std::pow(kSquare / round_, square);
            s = std::pow(std::pow(ub, e) + std::pow(uc, e), 1.0 / e);
        }
        return {float((s - 1.0) * std::min(hb, hc)), float(square), float(fitted)};
    }

private:
    // How well the section's box across axis a agrees with the view along a, in [0, 1]: the
    // share of the box that view covers. A section inscribed in the box covers pi/4 of it (an
    // ellipse), more where it is squarer; a box paired from runs of two views that the third
    // does not see there (an arm beside the body in one view, in front of it in the other)
    // covers much less: its lofted section would be ghost volume.
    double fit(int a, int b, const Interval& ib, const Interval& ic) const {
        const Projection& A = proj_[std::size_t(a)];
        const double area = double(ib.hi - ib.lo + 1) * double(ic.hi - ic.lo + 1);
        const double cover = b == A.u ? A.count(ib.lo, ib.hi, ic.lo, ic.hi) : A.count(ic.lo, ic.hi, ib.lo, ib.hi);
        return smoothstep(cover / area, kFitLow, kFitHigh);
    }

    // The run along axis `along` through p's projection along axis k (empty when p projects
    // outside).
    Interval run(int k, int along, const Coord& p) const {
        const Projection& P = proj_[std::size_t(k)];
        if (!P.inside(p[P.u], p[P.v])) return {};
        const std::size_t i = P.index(p[P.u], p[P.v]);
        return along == P.u ? Interval{P.lo_u[i], P.hi_u[i]} : Interval{P.lo_v[i], P.hi_v[i]};
    }

    // The facts of the box (ib, ic) across axis a at p, from `memo` when it holds them.
    BoxFacts box_facts(int a, int b, int c, const Coord& p, const Interval& ib, const Interval& ic,
                       BoxMemo* memo) const {
        BoxFacts* slot = memo ? &(*memo)[std::size_t(a)][std::size_t(p[a] & 7)] : nullptr;
        if (slot && slot->station == p[a] && slot->ib.lo == ib.lo && slot->ib.hi == ib.hi && slot->ic.lo == ic.lo &&
            slot->ic.hi == ic.hi)
            return *slot;
        const Projection& A = proj_[std::size_t(a)];
        const int mb = int(std::lround(ib.mid())), mc = int(std::lround(ic.mid()));
        const auto outside = [&](int vb, int vc) {
            Coord q = p;
            q[b] = vb;
            q[c] = vc;
            return !A.inside(q[A.u], q[A.v]);
        };
        BoxFacts facts;
        facts.station = p[a];
        facts.ib = ib;
        facts.ic = ic;
        facts.sides =
            outside(ib.lo - 2, mc) && outside(ib.hi + 2, mc) && outside(mb, ic.lo - 2) && outside(mb, ic.hi + 2);
        facts.fit = fit(a, b, ib, ic);
        if (slot) *slot = facts;
        return facts;
    }

    // How square the section across axis a at p is, in [0, 1], where the view along a shows
    // the box's four sides as its outline (a straight edge of that view, not a part hidden
    // inside it; box_facts): its box must stay the same along a over the box's own half-width
    // (the walls are straight: a prism along a). Then that view is the section (a box, the
    // disc of a standing cylinder, the triangle of a wedge) and the prior leaves the hull
    // alone there.
    double squareness(int a, int b, int c, const Coord& p, const Interval& ib, const Interval& ic) const {
        // The extent along a: where both runs along a through p hold.
        const Interval ab = run(c, a, p), ac = run(b, a, p);
        const Interval along{std::max(ab.lo, ac.lo), std::min(ab.hi, ac.hi)};
        const int reach = std::max(1, int(std::lround(std::min(ib.half(), ic.half()))));
        double q = 1.0;
        for (int s = -1; s <= 1; s += 2) {
            Coord n = p;
            n[a] = std::clamp(p[a] + s * reach, std::min(along.lo + 1, p[a]), std::max(along.hi - 1, p[a]));
            q = std::min({q, jaccard(ib, run(c, b, n)), jaccard(ic, run(b, c, n))});
        }
        return smoothstep(q, 0.85, 0.97);
    }

    double round_;
    const std::array<Projection, 3>& proj_;
    PairedBoxes pairs_;
};

} // namespace

void loft_by_leaf(const HullVoxels& vox, const std::array<Projection, 3>& proj, double round_exponent,
                  const std::vector<LeafMask>* only, const LoftLeafBody& body) {
    const Lofter lofter(proj, vox.maxdim, round_exponent);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::uint32_t> index;
        std::vector<LoftValue> values;
        index.reserve(LeafT::SIZE);
        values.reserve(LeafT::SIZE);
        BoxMemo memo;
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const LeafT& leaf = vox.leaves.leaf(l);
            index.clear();
            values.clear();
            vox.for_leaf(l, only ? &(*only)[l] : nullptr, [&](std::size_t i, openvdb::Index o) {
                index.push_back(std::uint32_t(i));
                values.push_back(lofter.value(leaf.offsetToGlobalCoord(o), nullptr, &memo));
            });
            body(index.data(), values.data(), values.size());
        }
    });
}

std::vector<LoftValue> loft_field(const HullVoxels& vox, double round_exponent) {
    std::vector<LoftValue> out(vox.n);
    loft_by_leaf(vox, project_hull(vox), round_exponent, nullptr,
                 [&](const std::uint32_t* index, const LoftValue* values, std::size_t count) {
                     for (std::size_t k = 0; k < count; ++k) out[index[k]] = values[k];
                 });
    return out;
}

} // namespace cm::plausible
