#include "load.h"

#include <algorithm>
#include <atomic>
#include <cstdio>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "align.h"
#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "opposite_holes.h"
#include "pockets.h"
#include "sheet.h"
#include "silhouette.h"
#include "silhouette_holes.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// A view whose manifest entry gives a mask: white (or alpha, where the mask has alpha
// that separates something) is the object, grey its fractional coverage. The mask stands
// for the drawing's segmentation; it must have the drawing's size.
SilhouetteResult silhouette_from_mask(const ManifestView& mv, const Image& image, int svg_size) {
    ImageInfo info;
    const Image m = read_image(mv.mask, &info, false, svg_size);
    if (m.width != image.width || m.height != image.height)
        throw Error("mask \"" + mv.mask.string() + "\" is " + std::to_string(m.width) + "x" + std::to_string(m.height) +
                    " but image \"" + mv.image.string() + "\" is " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + "; they must match");
    const std::size_t n = std::size_t(m.width) * m.height;
    std::size_t transparent = 0;
    if (info.has_alpha)
        for (std::size_t i = 0; i < n; ++i) transparent += m.pixels[i * 4 + 3] < 0.5f;
    const bool alpha = transparent > 0 && transparent < n;
    SilhouetteResult res;
    res.method = "mask";
    std::vector<float> coverage(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &m.pixels[i * 4];
        coverage[i] = std::clamp(alpha ? p[3] : (p[0] + p[1] + p[2]) / 3.0f, 0.0f, 1.0f);
    }
    res.coverage = Coverage(coverage, m.width, m.height);
    return res;
}

// The silhouette options of a view: its manifest entry's, the stage's keep where the
// entry says auto. A calibrated camera is a photograph's (drawings are not calibrated).
SilhouetteOptions silhouette_options(const ManifestView& mv, const LoadViewsOptions& opt) {
    SilhouetteOptions so;
    so.background = mv.background;
    so.threshold = mv.threshold.value_or(-1.0);
    so.keep = mv.keep != "auto" ? mv.keep : opt.keep;
    so.holes = mv.holes;
    so.close_gaps = mv.close_gaps.value_or(-1.0);
    so.shadow = mv.shadow;
    so.photo = mv.photo != "auto" ? mv.photo : mv.matrix ? "on" : "auto";
    return so;
}

// Drawn views get their pockets filled (pockets.h); photographs and views keeping every
// hole (`holes: keep`) keep theirs.
bool fills_pockets(const ManifestView& mv, const LoadViewsOptions& opt) {
    const SilhouetteOptions so = silhouette_options(mv, opt);
    return so.photo != "on" && so.holes != "keep";
}

// The pockets of every drawn view filled, counted per view into `filled`: once the
// silhouettes are extracted, and again once reconciliation has resampled them (a turn or
// a bend can make new ones).
void fill_drawn_pockets(const Manifest& man, const LoadViewsOptions& opt, Views& views,
                        std::vector<std::size_t>& filled) {
    filled.resize(man.views.size(), 0);
    tbb::parallel_for(std::size_t(0), man.views.size(), [&](std::size_t i) {
        if (fills_pockets(man.views[i], opt)) filled[i] += fill_pockets(views.views[i].coverage);
    });
}

// What the user should hear of a view's segmentation (marks dropped, a photograph's growth,
// blank regions filled); empty when there is nothing to say.
std::string segmentation_note(const SilhouetteResult& s, const SilhouetteOptions& so) {
    std::string note;
    if (s.components_dropped)
        note += "dropped " + std::to_string(s.components_dropped) +
                " separate mark(s) away from the object (keep: all keeps them)";
    if (s.photo) {
        if (!note.empty()) note += "; ";
        note += "segmented as a photograph: " + std::to_string(s.grown) +
                " px grown from the seeds beyond the threshold, " + std::to_string(s.regions_filled) +
                " enclosed region(s) filled (photo: off segments it as a drawing)";
    } else if (s.stroke.samples) {
        if (!note.empty()) note += "; ";
        char width[128];
        if (s.stroke.ink_placed)
            std::snprintf(width, sizeof width,
                          "line art: outline at its strokes' centre (stroke %.1f px; %.1f px by its ink, placed by it)",
                          s.stroke.stroke_width, s.stroke.ink_width);
        else
            std::snprintf(width, sizeof width, "line art: outline at its strokes' centre (stroke %.1f px)",
                          s.stroke.stroke_width);
        note += width;
    }
    if (const std::string holes = s.photo ? "" : describe_regions(s.regions); !holes.empty()) {
        if (!note.empty()) note += "; ";
        note += "enclosed blank regions: " + holes;
        if (so.holes == "auto" && s.regions_filled) note += " (holes: keep opens them)";
    }
    return note;
}

// The camera a view's manifest entry gives; a drawn view's scale and origin, unless fixed
// here, come from the alignment.
Camera camera_of(const ManifestView& mv) {
    Camera c = mv.matrix ? Camera::perspective(*mv.matrix)
               : mv.view ? *Camera::named(*mv.view)
                         : Camera::from_azimuth_elevation(*mv.azimuth, *mv.elevation);
    if (mv.scale) {
        c.scale = *mv.scale;
        c.cx = (*mv.origin)[0];
        c.cy = (*mv.origin)[1];
    }
    return c;
}

// One kind of camera per manifest, and a real size only for drawn views; true when the
// views are calibrated.
bool check_camera_kinds(const Manifest& man) {
    std::size_t perspective = 0;
    for (const auto& mv : man.views) perspective += mv.matrix.has_value();
    if (perspective != 0 && perspective != man.views.size())
        throw Error(man.file.string() + ": mixes calibrated (matrix) and drawn views; use one kind per manifest");
    if (perspective != 0 && (man.height || man.width || man.depth))
        throw Error(man.file.string() +
                    ": a real size (height, width, depth) applies to drawn views; calibrated views keep "
                    "the calibration's units");
    return perspective != 0;
}

// The views holding openings the opposite view confirmed, extracted again with those regions
// opened as holes: their edge then goes to the strokes' centre line as the outline's does
// (open_confirmed_holes opens the blank region alone, half a stroke short all round).
void extract_with_confirmed_holes(const Manifest& man, const LoadViewsOptions& opt, Views& views,
                                  const std::vector<std::vector<EnclosedRegion>>& regions,
                                  const std::vector<ImageInfo>& infos) {
    tbb::parallel_for(std::size_t(0), man.views.size(), [&](std::size_t i) {
        View& v = views.views[i];
        SilhouetteOptions so = silhouette_options(man.views[i], opt);
        for (const EnclosedRegion& g : regions[i]) // a confirmed region keeps its pixels
            if (g.hole && !g.pixels.empty())
                so.open_at.emplace_back(int(g.pixels[0] % std::uint32_t(v.width)),
                                        int(g.pixels[0] / std::uint32_t(v.width)));
        if (!so.open_at.empty()) v.coverage = extract_silhouette(v.image, infos[i], so).coverage;
    });
}

// Views read side by side, one view's image the chunk: its drawing (or its panel of a
// sheet), silhouette and camera. A stop is looked for per view and per step of a view
// (reading, extracting), from the workers; the notes go into `stats` in the views' order.
void read_views(const Manifest& man, const LoadViewsOptions& opt, Views& views, LoadViewsStats& stats,
                const Progress& progress) {
    PanelSearch search;
    search.svg_size = opt.svg_size;
    SheetViews sheets = split_sheets(man, search); // the panels of turnaround sheets, each a view's drawing
    stats.notes.insert(stats.notes.end(), sheets.notes.begin(), sheets.notes.end());
    std::vector<std::string> errors(man.views.size()), notes(man.views.size());
    std::vector<std::vector<EnclosedRegion>> regions(man.views.size());
    std::vector<ImageInfo> infos(man.views.size());
    std::atomic<std::size_t> steps{0};
    auto step = [&] {
        if (progress) progress(0.8 * double(steps++) / double(2 * man.views.size()));
    };
    tbb::parallel_for(std::size_t(0), man.views.size(), [&](std::size_t i) {
        const ManifestView& mv = man.views[i];
        View& v = views.views[i];
        step();
        try {
            v.name = mv.key;
            v.source = mv.image;
            ImageInfo& info = infos[i] = sheets.infos[i];
            v.image =
                sheets.on_sheet(i) ? std::move(sheets.images[i]) : read_image(mv.image, &info, true, opt.svg_size);
            v.width = v.image.width;
            v.height = v.image.height;
            step();
            const SilhouetteOptions so = silhouette_options(mv, opt);
            SilhouetteResult s = mv.mask.empty() ? extract_silhouette(v.image, info, so)
                                                 : silhouette_from_mask(mv, v.image, opt.svg_size);
            v.coverage = std::move(s.coverage);
            if (const std::string note = segmentation_note(s, so); !note.empty())
                notes[i] = "view \"" + v.name + "\": " + note;
            regions[i] = std::move(s.regions); // after the note, which lists them
            v.camera = camera_of(mv);
        } catch (const Cancelled&) {
            throw;
        } catch (const std::exception& e) {
            errors[i] = "view \"" + mv.key + "\": " + e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    for (const auto& n : notes)
        if (!n.empty()) stats.notes.push_back(n);
    const std::vector<std::string> confirmed = open_confirmed_holes(views.views, regions);
    stats.notes.insert(stats.notes.end(), confirmed.begin(), confirmed.end());
    if (!confirmed.empty()) extract_with_confirmed_holes(man, opt, views, regions, infos);
    fill_drawn_pockets(man, opt, views, stats.pockets_filled);
}

// Calibrated views keep the manifest's box; drawn views are aligned into the output frame.
void place_views(const Manifest& man, const LoadViewsOptions& opt, Views& views, LoadViewsStats& stats) {
    if (views.calibrated) {
        if (man.bounds) {
            views.has_bounds = true;
            views.bounds_min = {(*man.bounds)[0], (*man.bounds)[1], (*man.bounds)[2]};
            views.bounds_max = {(*man.bounds)[3], (*man.bounds)[4], (*man.bounds)[5]};
        }
        return;
    }
    AlignOptions ao;
    ao.height = man.height;
    ao.width = man.width;
    ao.depth = man.depth;
    ao.tolerance = opt.align_tolerance;
    for (const auto& mv : man.views) ao.fixed.push_back(mv.scale.has_value());
    ao.bounds = man.bounds;
    const bool fixed = std::find(ao.fixed.begin(), ao.fixed.end(), true) != ao.fixed.end();
    if (opt.reconcile == "off" || fixed) {
        // Fixed cameras are the user's word on where each view stands: nothing moves them.
        align_views(views, ao, stats.warnings);
        return;
    }
    // Reconciled views are told what moved instead of how far their axes were apart.
    std::vector<std::string> disagreements;
    align_views(views, ao, disagreements);
    ReconcileOptions ro;
    std::string primary;
    for (std::size_t i = 0; i < man.views.size(); ++i) {
        if (!man.views[i].primary) continue;
        if (!primary.empty())
            throw Error(man.file.string() + ": views \"" + primary + "\" and \"" + man.views[i].key +
                        "\" are both marked primary: one view at most stays as drawn");
        primary = man.views[i].key;
        ro.primary = i;
    }
    ro.opposite = opt.opposite;
    ro.tolerance = opt.align_tolerance;
    ro.bend = opt.bend;
    ro.stretch = opt.stretch;
    stats.reconciled = reconcile_views(views, ro, stats.warnings);
}

// A silhouette's area: its coverage summed in fixed blocks of pixels (the same figure on
// every run and machine).
double silhouette_area(const Coverage& c) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, c.size(), std::size_t(1) << 16), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double sum) {
            // In pixel order, leaving out the zeros beyond the window (adding them changes no
            // sum).
            const std::size_t W = std::size_t(c.width());
            for (std::size_t y = r.begin() / W; y * W < r.end(); ++y) {
                const float* row = c.window_row(int(y));
                if (!row) continue;
                const std::size_t left = y * W + std::size_t(c.x0());
                const std::size_t a = std::max(r.begin(), left);
                const std::size_t b = std::min(r.end(), left + std::size_t(c.window_width()));
                for (std::size_t i = a; i < b; ++i) sum += row[i - left];
            }
            return sum;
        },
        [](double x, double y) { return x + y; });
}

} // namespace

void LoadViewsOptions::declare(ParamBinder& b) {
    b.add(keep, ParamSpec::Enum("keep", "auto", {"auto", "largest", "all"},
                                "which separate marks to keep: auto drops specks and small marks (a "
                                "view's own keep wins)"));
    b.add(align_tolerance, ParamSpec::Float("align_tolerance", 0.02, 0.0, 1.0, "ratio",
                                            "relative disagreement between views on a shared axis that raises a "
                                            "warning"));
    b.add(reconcile, ParamSpec::Enum("reconcile", "on", {"on", "off"},
                                     "reconcile drawn views that disagree: each view but the primary may scale its "
                                     "image axes apart, turn and bend slightly so that what the views share agrees "
                                     "(off: one scale and placement per view)"));
    b.add(opposite, ParamSpec::Enum("opposite", "union", {"union", "intersect", "primary"},
                                    "views along one line of sight (front and back, ...): keep what either draws "
                                    "(union), what both draw (intersect) or what the primary draws"));
    b.add(bend, ParamSpec::Float("bend", 0.05, 0.0, 0.1, "ratio",
                                 "how far a view's outline may grow to keep what another view draws beyond it (an "
                                 "axis drawn longer, a part drawn wider), a ratio of the silhouette's longest side; "
                                 "a larger disagreement is carved and reported"));
    b.add(svg_size, ParamSpec::Int("svg_size", kDefaultSvgSize, 64, 16384, "px",
                                   "the longer side at which SVG drawings are drawn (by librsvg, on white paper): "
                                   "at least 4 times the hull's resolution keeps the outline finer than the grid"));
    b.add(stretch, ParamSpec::Enum("stretch", "uniform", {"uniform", "axes"},
                                   "how a reconciled view may scale: uniform keeps each drawing's proportions (one "
                                   "scale, turned and bent); axes scales its two image axes apart, so that views "
                                   "drawn off along one axis agree (the drawing's proportions change)"));
}

void LoadViewsStats::report(Metrics& m) const {
    for (const auto& w : warnings) m.warn(w);
    m.count("views", names.size());
    std::size_t pockets = 0;
    for (std::size_t p : pockets_filled) pockets += p;
    m.count("pockets_filled", pockets);
    for (std::size_t i = 0; i < names.size(); ++i) m.metric("silhouette_area_px." + names[i], silhouette_area_px[i]);
    for (const auto& r : reconciled) {
        if (!r.reconciled) continue;
        const std::string k = "reconcile." + r.name + ".";
        m.metric(k + "scale_x", r.scale_x);
        m.metric(k + "scale_y", r.scale_y);
        m.metric(k + "turn_deg", r.turn_deg);
        m.metric(k + "warp_px", r.warp_px);
        m.metric(k + "missing_pct", r.missing_pct);
    }
    if (bounds_size) {
        const Vec3d& e = *bounds_size;
        m.metric_json("bounds_size",
                      "[" + std::to_string(e.x) + "," + std::to_string(e.y) + "," + std::to_string(e.z) + "]");
    }
}

Result<Views, LoadViewsStats> load_views(const fs::path& manifest, const LoadViewsOptions& opt, Progress progress) {
    const Manifest man = read_manifest(manifest);
    Result<Views, LoadViewsStats> r;
    Views& views = r.value;
    LoadViewsStats& stats = r.stats;
    views.manifest = man.file;
    views.views.resize(man.views.size());
    views.calibrated = check_camera_kinds(man);
    read_views(man, opt, views, stats, progress);
    if (progress) progress(0.8);
    for (const auto& v : views.views) {
        if (v.coverage.inside_box().empty())
            throw Error("view \"" + v.name + "\" (" + v.source.string() +
                        ") has an empty silhouette: no object was found in it");
    }
    place_views(man, opt, views, stats);
    if (!views.calibrated) fill_drawn_pockets(man, opt, views, stats.pockets_filled);
    for (std::size_t i = 0; i < views.views.size(); ++i)
        if (stats.pockets_filled[i])
            stats.notes.push_back("view \"" + views.views[i].name + "\": " + std::to_string(stats.pockets_filled[i]) +
                                  " enclosed pocket(s) of partial coverage (under " + std::to_string(kStrokeGapArea) +
                                  " px of paper each) filled as paper between strokes");
    for (const auto& v : views.views) {
        stats.names.push_back(v.name);
        stats.silhouette_area_px.push_back(silhouette_area(v.coverage));
    }
    if (views.has_bounds) stats.bounds_size = views.bounds_max - views.bounds_min;
    return r;
}

Image silhouette_image(const View& v) { return Image{v.width, v.height, 1, v.coverage.full(), {}}; }

} // namespace cm
