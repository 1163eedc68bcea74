// Parts traced along the slicing axis, for the lofted prior (plausible_loft.cpp). At a station
// along grid axis a, the hull's section pairs every run along b of the projection along c with
// every run along c of the projection along b: two legs apart in both views make four boxes,
// two of them ghosts that no line of sight needs. Each projection's runs are linked station to
// station into tracks (a run overlapping exactly one run of the next station, and that one
// only it: a leg from its foot to where it meets the other or the body). Two tracks of the two
// views sharing enough stations are taken for one part where their free ends (a foot, a head:
// a run with nothing next to it) lie at the same stations in both views, and ruled out where
// they do not, or where the view along a leaves their box mostly empty at some station they
// share (the footprint). A box is dropped where its pair is ruled out and both its runs have a
// confirmed partner at that station: every line of sight through it along b and along c still
// crosses a kept box. Where the evidence does not tell the pairs apart, every box stays.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "plausible_projection.h"

namespace cm::plausible {

/// The runs of one projection linked into tracks along one of its axes (the slicing axis).
struct TrackMap {
    struct Track {
        int lo = 0, hi = -1;                 ///< the stations it spans
        bool tip_lo = false, tip_hi = false; ///< its end is free (nothing beyond), not a merge
    };
    int a = 0;                    ///< the slicing axis (the projection's u or v)
    int origin = 0;               ///< the first station
    std::vector<std::int32_t> id; ///< per pixel of the projection: its run's track, -1 outside
    std::vector<Track> tracks;
    /// Per station (from `origin`): its runs across a, lowest first, and their tracks.
    std::vector<std::vector<std::pair<Interval, std::int32_t>>> runs;
};

/// @brief Tracks of the runs of `P` across its axis `a` (a is P.u or P.v).
TrackMap trace_tracks(const Projection& P, int a);

/// @brief The ghost boxes of the three slicing axes (see above).
class PairedBoxes {
public:
    /// `proj`: the hull's projections along x, y and z; `maxdim`: the hull's longest side, cells.
    PairedBoxes(const std::array<Projection, 3>& proj, int maxdim);
    /// Whether the box across axis a through p (its runs through p's projections along c and b)
    /// pairs two parts' runs that the evidence rules out.
    bool dropped(int a, const Coord& p) const;
    /// The number of boxes dropped, over every axis and station.
    std::size_t boxes() const { return boxes_; }

private:
    void pair_axis(int a, int maxdim);
    std::int32_t track_at(const TrackMap& T, const Projection& P, const Coord& p) const;

    const std::array<Projection, 3>& proj_;
    /// Per slicing axis a: the tracks of the runs along b (projection along c) and along c
    /// (projection along b).
    std::array<TrackMap, 3> tb_, tc_;
    /// Per slicing axis, per station (from the box's lower corner): the dropped (track along b,
    /// track along c) pairs.
    std::array<std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>>, 3> drop_;
    std::array<int, 3> origin_{};
    std::size_t boxes_ = 0;
};

} // namespace cm::plausible
