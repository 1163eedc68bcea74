// Parts traced along the slicing axis and the boxes their pairing rules out
// (plausible_tracks.h).
#include "plausible_tracks.h"

#include "plausible_state.h"

#include <algorithm>
#include <cstdlib>
#include <unordered_map>

namespace cm::plausible {

namespace {

// The view along the slicing axis covering at most this share of a pair's box at some station
// they share rules the pair out; at least kCoverIn at every one of them confirms it.
constexpr double kCoverOut = 0.3, kCoverIn = 0.55;
// More stations per side than this many pairs are not weighed (a ragged outline).
constexpr std::size_t kMaxRuns = 8;

bool overlap(const Interval& x, const Interval& y) { return x.lo <= y.hi && y.lo <= x.hi; }

std::size_t degree(const Interval& x, const std::vector<std::pair<Interval, std::int32_t>>& row) {
    std::size_t n = 0;
    for (const auto& r : row) n += overlap(x, r.first);
    return n;
}

std::uint64_t key(std::int32_t tb, std::int32_t tc) {
    return std::uint64_t(std::uint32_t(tb)) << 32 | std::uint32_t(tc);
}

} // namespace

TrackMap trace_tracks(const Projection& P, int a) {
    TrackMap T;
    T.a = a;
    const bool along_u = a == P.u; // stations along u, runs along v
    const int na = along_u ? P.nu : P.nv, nr = along_u ? P.nv : P.nu;
    const int r0 = along_u ? P.v0 : P.u0;
    T.origin = along_u ? P.u0 : P.v0;
    T.id.assign(P.in.size(), -1);
    T.runs.resize(std::size_t(na));
    const auto pixel = [&](int s, int r) {
        return along_u ? std::size_t(s) * std::size_t(P.nv) + std::size_t(r)
                       : std::size_t(r) * std::size_t(P.nv) + std::size_t(s);
    };
    for (int s = 0; s < na; ++s)
        for (int r = 0; r < nr;) {
            if (!P.in[pixel(s, r)]) {
                ++r;
                continue;
            }
            int e = r;
            while (e + 1 < nr && P.in[pixel(s, e + 1)]) ++e;
            T.runs[std::size_t(s)].push_back({Interval{r0 + r, r0 + e}, -1});
            r = e + 1;
        }
    for (int s = 0; s < na; ++s) {
        auto& row = T.runs[std::size_t(s)];
        for (auto& run : row) {
            std::int32_t t = -1;
            std::size_t up = 0;
            if (s > 0) {
                const auto& prev = T.runs[std::size_t(s - 1)];
                up = degree(run.first, prev);
                if (up == 1)
                    for (const auto& q : prev)
                        if (overlap(run.first, q.first) && degree(q.first, row) == 1) t = q.second;
            }
            if (t < 0) {
                t = std::int32_t(T.tracks.size());
                T.tracks.push_back({T.origin + s, T.origin + s, up == 0, false});
            }
            run.second = t;
            TrackMap::Track& tr = T.tracks[std::size_t(t)];
            tr.hi = T.origin + s;
            tr.tip_hi = s + 1 == na || degree(run.first, T.runs[std::size_t(s + 1)]) == 0;
            for (int r = run.first.lo; r <= run.first.hi; ++r) T.id[pixel(s, r - r0)] = t;
        }
    }
    return T;
}

PairedBoxes::PairedBoxes(const std::array<Projection, 3>& proj, int maxdim) : proj_(proj) {
    for (int a = 0; a < 3; ++a) pair_axis(a, maxdim);
}

void PairedBoxes::pair_axis(int a, int maxdim) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const Projection &Pa = proj_[std::size_t(a)], &Pb = proj_[std::size_t(b)], &Pc = proj_[std::size_t(c)];
    TrackMap& TB = tb_[std::size_t(a)] = trace_tracks(Pc, a);
    TrackMap& TC = tc_[std::size_t(a)] = trace_tracks(Pb, a);
    origin_[std::size_t(a)] = TB.origin;
    const std::size_t na = std::min(TB.runs.size(), TC.runs.size());
    drop_[std::size_t(a)].assign(na, {});
    // The least share of its box the view along a covers, per pair of tracks, over the
    // stations they share.
    const auto share = [&](const Interval& ib, const Interval& ic) {
        const double n = b == Pa.u ? Pa.count(ib.lo, ib.hi, ic.lo, ic.hi) : Pa.count(ic.lo, ic.hi, ib.lo, ib.hi);
        return n / (double(ib.size()) * double(ic.size()));
    };
    std::unordered_map<std::uint64_t, double> cover;
    for (std::size_t s = 0; s < na; ++s) {
        const auto &RB = TB.runs[s], &RC = TC.runs[s];
        if (RB.size() > kMaxRuns || RC.size() > kMaxRuns || (RB.size() < 2 && RC.size() < 2)) continue;
        for (const auto& [ib, tb] : RB)
            for (const auto& [ic, tc] : RC) {
                const double sh = share(ib, ic);
                auto [it, fresh] = cover.try_emplace(key(tb, tc), sh);
                if (!fresh) it->second = std::min(it->second, sh);
            }
    }
    // Free ends at the same station in both views: one part's foot. The hull's projections of
    // one part end at the same station; allow a cell or two for the grid.
    const double good_ends = 1.0 + double(maxdim) / 256.0, bad_ends = 3.0 + 2.0 * double(maxdim) / 256.0;
    const int min_shared = std::max(3, maxdim / 16);
    // -1 ruled out, 1 confirmed, 0 not told.
    const auto verdict = [&](std::int32_t tb, std::int32_t tc) {
        const auto it = cover.find(key(tb, tc));
        const double cov = it == cover.end() ? 1.0 : it->second;
        const TrackMap::Track &x = TB.tracks[std::size_t(tb)], &y = TC.tracks[std::size_t(tc)];
        // Tracks sharing a few stations only (a part's tip beside another's run) tell nothing.
        if (std::min(x.hi, y.hi) - std::max(x.lo, y.lo) + 1 < min_shared) return 0;
        int ends = 0, off = 0;
        if (x.tip_lo && y.tip_lo) ++ends, off += std::abs(x.lo - y.lo);
        if (x.tip_hi && y.tip_hi) ++ends, off += std::abs(x.hi - y.hi);
        if (cov <= kCoverOut || (ends > 0 && double(off) > bad_ends)) return -1;
        if (cov >= kCoverIn && (ends == 0 || double(off) <= good_ends)) return 1;
        return 0;
    };
    for (std::size_t s = 0; s < na; ++s) {
        const auto &RB = TB.runs[s], &RC = TC.runs[s];
        if (RB.size() < 2 || RC.size() < 2 || RB.size() > kMaxRuns || RC.size() > kMaxRuns) continue;
        int v[kMaxRuns][kMaxRuns];
        for (std::size_t i = 0; i < RB.size(); ++i)
            for (std::size_t j = 0; j < RC.size(); ++j) v[i][j] = verdict(RB[i].second, RC[j].second);
        for (std::size_t i = 0; i < RB.size(); ++i)
            for (std::size_t j = 0; j < RC.size(); ++j) {
                if (v[i][j] >= 0) continue;
                bool row = false, col = false;
                for (std::size_t k = 0; k < RC.size(); ++k) row |= k != j && v[i][k] > 0;
                for (std::size_t k = 0; k < RB.size(); ++k) col |= k != i && v[k][j] > 0;
                if (!row || !col) continue;
                drop_[std::size_t(a)][s].push_back({RB[i].second, RC[j].second});
                ++boxes_;
            }
    }
}

std::int32_t PairedBoxes::track_at(const TrackMap& T, const Projection& P, const Coord& p) const {
    return P.inside(p) ? T.id[P.index(p[P.u], p[P.v])] : -1;
}

bool PairedBoxes::dropped(int a, const Coord& p) const {
    const auto& stations = drop_[std::size_t(a)];
    const int s = p[a] - origin_[std::size_t(a)];
    if (s < 0 || std::size_t(s) >= stations.size() || stations[std::size_t(s)].empty()) return false;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const std::int32_t tb = track_at(tb_[std::size_t(a)], proj_[std::size_t(c)], p);
    const std::int32_t tc = track_at(tc_[std::size_t(a)], proj_[std::size_t(b)], p);
    for (const auto& [x, y] : stations[std::size_t(s)])
        if (x == tb && y == tc) return true;
    return false;
}

} // namespace cm::plausible
