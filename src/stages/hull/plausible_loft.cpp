// The lofted prior of hull.plausible (prior: loft; plausible_loft.h). A modeller lofting from
// blueprints sweeps a cross-section along the object, scaled at each station to the extents
// the other views give, rounded where the drawings show curves and kept square where they
// show straight walls meeting at corners. Here the "drawings" are the hull's projections along
// the grid's three axes (for the named views front/right/top they are the drawings
// themselves, at the grid's pitch), so the prior needs no view to lie along an axis and takes
// any set of views.
#include "plausible_loft.h"

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

double smoothstep(double x, double a, double b) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The hull projected along one grid axis k: a mask over the other two axes (u = the lower,
// v = the higher), and per inside pixel the bounds of its run along u and along v.
struct Projection {
    int k = 0, u = 0, v = 0;
    int u0 = 0, v0 = 0, nu = 0, nv = 0;
    std::vector<std::uint8_t> in;
    std::vector<std::int32_t> lo_u, hi_u, lo_v, hi_v;
    // Summed-area table of `in`, (nu + 1) x (nv + 1): sat[(iu + 1, iv + 1)] counts the inside
    // pixels up to and including (iu, iv) (local indices).
    std::vector<std::int32_t> sat;

    // Inside pixels in the box [u0, u1] x [v0, v1] (grid coordinates), clamped to the array.
    double count(int a0, int a1, int b0, int b1) const {
        a0 = std::max(a0 - u0, 0);
        b0 = std::max(b0 - v0, 0);
        a1 = std::min(a1 - u0, nu - 1);
        b1 = std::min(b1 - v0, nv - 1);
        if (a1 < a0 || b1 < b0) return 0.0;
        const std::size_t w = std::size_t(nv) + 1;
        const auto at = [&](int i, int j) { return double(sat[std::size_t(i) * w + std::size_t(j)]); };
        return at(a1 + 1, b1 + 1) - at(a0, b1 + 1) - at(a1 + 1, b0) + at(a0, b0);
    }

    std::size_t index(int iu, int iv) const { return std::size_t(iu - u0) * std::size_t(nv) + std::size_t(iv - v0); }
    bool inside(int iu, int iv) const {
        return iu >= u0 && iv >= v0 && iu < u0 + nu && iv < v0 + nv && in[index(iu, iv)] != 0;
    }
};

struct Interval {
    int lo = 0, hi = -1;
    bool empty() const { return hi < lo; }
    double half() const { return 0.5 * double(hi - lo) + 0.5; } // the voxels' extent, cells
    double mid() const { return 0.5 * double(lo + hi); }
};

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
    Lofter(const HullVoxels& vox, double round_exponent) : round_(round_exponent) {
        for (int k = 0; k < 3; ++k) project(vox, k);
        mark_inside(vox);
        for (auto& P : proj_) tabulate(P);
    }

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
    void project(const HullVoxels& vox, int k) {
        Projection& P = proj_[std::size_t(k)];
        P.k = k;
        P.u = k == 0 ? 1 : 0;
        P.v = k == 2 ? 1 : 2;
        P.u0 = vox.box.min()[P.u];
        P.v0 = vox.box.min()[P.v];
        P.nu = vox.box.dim()[P.u];
        P.nv = vox.box.dim()[P.v];
        P.in.assign(std::size_t(P.nu) * std::size_t(P.nv), 0);
    }

    // The three projections' inside pixels, in parallel over leaves: each leaf's voxels are
    // projected into an 8 x 8 mask per axis first, so the arrays see one store per pixel.
    void mark_inside(const HullVoxels& vox) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                const LeafT& leaf = vox.leaves.leaf(l);
                const auto& mask = leaf.getValueMask();
                std::array<std::uint64_t, 3> local{};
                for (openvdb::Index w = 0; w < LeafT::SIZE / 64; ++w)
                    for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1) {
                        const unsigned o = w * 64 + unsigned(__builtin_ctzll(word));
                        const std::array<unsigned, 3> c{o >> 6, (o >> 3) & 7u, o & 7u};
                        for (std::size_t k = 0; k < 3; ++k) {
                            const Projection& P = proj_[k];
                            local[k] |= std::uint64_t(1) << (c[std::size_t(P.u)] * 8 + c[std::size_t(P.v)]);
                        }
                    }
                const Coord origin = leaf.origin();
                for (std::size_t k = 0; k < 3; ++k) {
                    Projection& P = proj_[k];
                    for (std::uint64_t bits = local[k]; bits; bits &= bits - 1) {
                        const int b = __builtin_ctzll(bits);
                        // Leaves side by side along the axis share the pixel: relaxed stores of
                        // the same value.
                        std::atomic_ref<std::uint8_t>(P.in[P.index(origin[P.u] + b / 8, origin[P.v] + b % 8)])
                            .store(1, std::memory_order_relaxed);
                    }
                }
            }
        });
    }

    // The runs along u and v through each inside pixel, and the summed-area table.
    static void tabulate(Projection& P) {
        const std::size_t n = P.in.size();
        P.lo_u.assign(n, 0);
        P.hi_u.assign(n, -1);
        P.lo_v.assign(n, 0);
        P.hi_v.assign(n, -1);
        // Runs along v (rows of the array), then along u (its columns).
        tbb::parallel_for(0, P.nu, [&](int iu) { runs(P, std::size_t(iu) * P.nv, 1, P.nv, P.v0, P.lo_v, P.hi_v); });
        tbb::parallel_for(0, P.nv,
                          [&](int iv) { runs(P, std::size_t(iv), std::size_t(P.nv), P.nu, P.u0, P.lo_u, P.hi_u); });
        const std::size_t w = std::size_t(P.nv) + 1;
        P.sat.assign((std::size_t(P.nu) + 1) * w, 0);
        for (int iu = 0; iu < P.nu; ++iu)
            for (int iv = 0; iv < P.nv; ++iv)
                P.sat[std::size_t(iu + 1) * w + std::size_t(iv + 1)] =
                    P.sat[std::size_t(iu) * w + std::size_t(iv + 1)] +
                    P.sat[std::size_t(iu + 1) * w + std::size_t(iv)] - P.sat[std::size_t(iu) * w + std::size_t(iv)] +
                    P.in[P.index(iu + P.u0, iv + P.v0)];
    }

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

    static void runs(const Projection& P, std::size_t first, std::size_t stride, int count, int origin,
                     std::vector<std::int32_t>& lo, std::vector<std::int32_t>& hi) {
        for (int i = 0; i < count;) {
            if (!P.in[first + std::size_t(i) * stride]) {
                ++i;
                continue;
            }
            int j = i;
            while (j + 1 < count && P.in[first + std::size_t(j + 1) * stride]) ++j;
            for (int t = i; t <= j; ++t) {
                lo[first + std::size_t(t) * stride] = origin + i;
                hi[first + std::size_t(t) * stride] = origin + j;
            }
            i = j + 1;
        }
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
    std::array<Projection, 3> proj_;
};

} // namespace

void loft_by_leaf(const HullVoxels& vox, double round_exponent, const std::vector<LeafMask>* only,
                  const LoftLeafBody& body) {
    const Lofter lofter(vox, round_exponent);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<LoftValue> values;
        values.reserve(LeafT::SIZE);
        BoxMemo memo;
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const LeafT& leaf = vox.leaves.leaf(l);
            values.clear();
            for (auto it = leaf.cbeginValueOn(); it; ++it) {
                const openvdb::Index o = it.pos();
                const bool wanted = !only || ((*only)[l][o >> 6] >> (o & 63) & 1);
                values.push_back(wanted ? lofter.value(it.getCoord(), nullptr, &memo) : LoftValue{});
            }
            body(vox.base[l], values.data(), values.size());
        }
    });
}

std::vector<LoftValue> loft_field(const HullVoxels& vox, double round_exponent) {
    std::vector<LoftValue> out(vox.n);
    loft_by_leaf(vox, round_exponent, nullptr, [&](std::size_t first, const LoftValue* values, std::size_t count) {
        std::copy(values, values + count, out.begin() + std::ptrdiff_t(first));
    });
    return out;
}

} // namespace cm::plausible
