// The state of a reconciliation (reconcile.h), shared by its parts: reconcile.cpp (the
// fit, the turn search, resampling, merging) and reconcile_bend.cpp (the bend, the
// warnings). Internal to the views family.
#pragma once
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "reconcile.h"
#include "reconcile_grid.h"

namespace cm::reconcile_detail {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// Drawn pixel p to reconciled pixel q = c + t + K R(theta) (p - c): a turn about the
// silhouette's centre c, a stretch of each image axis, and a shift that keeps the centre.
struct Affine {
    Vec2d c{0, 0}, t{0, 0};
    double kx = 1, ky = 1, theta = 0;
    Vec2d inv(const Vec2d& q) const {
        const double dx = (q.x - c.x - t.x) / kx, dy = (q.y - c.y - t.y) / ky;
        const double cs = std::cos(theta), sn = std::sin(theta);
        return {c.x + cs * dx + sn * dy, c.y - sn * dx + cs * dy};
    }
    Vec2d fwd(const Vec2d& p) const {
        const double dx = p.x - c.x, dy = p.y - c.y, cs = std::cos(theta), sn = std::sin(theta);
        return {c.x + t.x + kx * (cs * dx - sn * dy), c.y + t.y + ky * (sn * dx + cs * dy)};
    }
};

// Bilinear coverage at continuous pixel coordinates (pixel i spans [i, i + 1)).
inline float sample(const Coverage& cov, double x, double y) {
    const double fx = x - 0.5, fy = y - 0.5;
    const int i = int(std::floor(fx)), j = int(std::floor(fy));
    const float ax = float(fx - i), ay = float(fy - j);
    return (1 - ay) * ((1 - ax) * cov.at(i, j) + ax * cov.at(i + 1, j)) +
           ay * ((1 - ax) * cov.at(i, j + 1) + ax * cov.at(i + 1, j + 1));
}

inline const char* axis_word(int k) { return k == 0 ? "width" : k == 1 ? "height" : "depth"; }

// One axis view taking part.
struct Member {
    std::size_t index = 0;
    int ar = -1, au = -1; // world axes of image x and y
    bool primary = false;
    std::vector<Vec2d> boundary; // centres of the silhouette's boundary pixels
    Vec2d pad{0, 0};             // extent beyond the boundary centres, per side
    Affine T;
    Vec2d offset{0, 0}; // where the reconciled canvas grew to the left and top
    Vec2d fine{0, 0};   // a follower's shift beyond centring, from its overlap with the anchor
    Vec2d mid{0, 0};    // the turned extent's centre, relative to T.c
    double w = 0, h = 0;
    Camera cam;
    bool applied = false; // T is in the silhouette now
};

class Reconciler {
public:
    Reconciler(Views& views, const ReconcileOptions& opt, std::vector<std::string>& warnings)
        : views_(views), opt_(opt), warnings_(warnings) {}

    std::vector<ViewReconciliation> run();

private:
    void setup();
    void fit();
    void place_followers();
    AxisMask mask_of(const Member& m, const ReconcileGrid& g) const;
    ReconcileGrid grid(int cells) const;
    // Masks of every member (the drawing through T until it is applied), then the merged
    // mask of every line of sight.
    std::vector<AxisMask> member_masks(const ReconcileGrid& g) const;
    /// `mode` "": the options' (what is carved); the search and the bend take the union, so
    /// that what one opposite view alone draws is neither turned nor bent away.
    std::vector<AxisMask> group_masks(const std::vector<AxisMask>& m, const std::string& mode = "") const;
    std::vector<double> missing_shares(int cells) const;
    double score() const;
    void search_turns();
    bool moved(const Member& m) const;
    void resample(Member& m);
    void merge_opposites();
    void bend();
    /// Bends a member's silhouette and drawing by a smooth warp (reconcile_warp.cpp) until
    /// they cover the pixel rects (x0, y0, x1, y1), its displacement at most `cap` pixels,
    /// growing its canvas; returns the warp's largest displacement.
    double warp(Member& m, const std::vector<std::array<double, 4>>& rects, double cap);
    /// Grows a member's canvas by the given pixels on each side (none where not positive),
    /// moving its camera with the drawing; the new paper repeats the drawing's edge.
    void grow_canvas(Member& m, int left, int top, int right, int bottom);
    /// Per world axis, the span of the applied members' silhouettes measuring it: their union
    /// (`all` true) or their intersection.
    std::pair<Vec3d, Vec3d> silhouette_span(bool all) const;
    /// The box to the views' intersection span, moved into the output frame (bottom centre
    /// at the origin) with every orthographic camera.
    void settle_box();
    void warn_moved(const Member& m, const ViewReconciliation& r);

    Views& views_;
    const ReconcileOptions& opt_;
    std::vector<std::string>& warnings_;
    std::vector<Member> members_;
    std::vector<std::vector<std::size_t>> groups_; // members by line of sight; the primary (or first) first
    std::vector<std::size_t> group_of_;
    std::vector<std::size_t> anchor_; // per member: the first of its line of sight (itself if so)
    std::array<double, 3> size_{0, 0, 0};
    // Once the members are applied, the grids span every silhouette (their union), so that
    // what one drawing draws beyond the fitted box is seen, bent for and counted.
    bool span_set_ = false;
    std::pair<Vec3d, Vec3d> span_;
    std::vector<double> warp_px_;
    int search_cells_ = 128, fine_cells_ = 384;
};

} // namespace cm::reconcile_detail
