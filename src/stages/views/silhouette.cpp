#include "silhouette.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>

#include <tbb/parallel_for.h>

#include "background_model.h"
#include "border_clusters.h"
#include "components.h"
#include "core/error.h"
#include "gaps.h"
#include "ink.h"
#include "io/manifest.h"
#include "line_art.h"
#include "line_holes.h"
#include "opening_parts.h"
#include "photo.h"
#include "pixel_flood.h"
#include "shadow.h"
#include "sheet.h"
#include "silhouette_holes.h"
#include "thin_outline.h"

namespace cm {

namespace {

// The object in a drawing as what is not its background: per pixel the colour distance to
// the background field, the background itself (what the border reaches, and the holes),
// and the coverage read from those.
class BackgroundCut {
public:
    // Each further border colour (a cloth reaching the frame) is a background too where it
    // reaches from the border: there a pixel's distance is to the nearest background, in
    // units of that background's threshold.
    BackgroundCut(const BackgroundCut&) = delete; // bgc_ points into source_
    BackgroundCut& operator=(const BackgroundCut&) = delete;
    // `img` may be a window of a larger image: (ox, oy) is where it starts there, full_w x
    // full_h that image's size (0: `img` is the whole image), for the background model.
    BackgroundCut(const Image& img, const BackgroundModel& model, double t, const std::vector<BorderCluster>& more,
                  int ox = 0, int oy = 0, int full_w = 0, int full_h = 0)
        : img_(img),
          w_(img.width),
          h_(img.height),
          n_(std::size_t(w_) * h_),
          t_(t),
          d_(n_),
          source_(n_, 0),
          bg_(n_, 0) {
        bgc_.model = model;
        for (const auto& c : more) bgc_.others.push_back(c.colour);
        bgc_.source = &source_;
        bgc_.w = w_;
        bgc_.h = h_;
        bgc_.ox = ox;
        bgc_.oy = oy;
        bgc_.full_w = full_w;
        bgc_.full_h = full_h;
        std::vector<std::vector<char>> reach;
        for (const auto& c : more) reach.push_back(cluster_reach(img, c));
        // Each pixel on its own: rows in parallel.
        tbb::parallel_for(0, h_, [&](int y) {
            const std::size_t row = std::size_t(y) * w_;
            bgc_.model_distance_row(img_, y, &d_[row]);
            if (more.empty()) return;
            for (int x = 0; x < w_; ++x) {
                const std::size_t i = row + x;
                const auto p = img_.rgba(i);
                for (std::size_t k = 0; k < more.size(); ++k) {
                    if (!reach[k][i]) continue; // only where that background reaches from the border
                    const double dc = more[k].distance({p[0], p[1], p[2]}) * t_ / more[k].threshold;
                    if (dc < d_[i]) {
                        d_[i] = dc;
                        source_[i] = static_cast<unsigned char>(k + 1);
                    }
                }
            }
        });
    }

    // Faint ink 8-connected to clear ink is ink (see raise_weak_ink).
    std::size_t raise_weak_ink(double weak) { return cm::raise_weak_ink(d_, t_, weak, w_, h_); }

    // Background: background-coloured pixels 4-connected to the border (so a line drawn
    // with 8-connected pixels closes a region). The ink closed over gaps up to `gap` px
    // (see close_ink) bars the way, so a break in an outline does not let the background
    // in; the object keeps the ink's own outer edge.
    void flood_from_border(double gap) {
        std::vector<char> ink(n_);
        for (std::size_t i = 0; i < n_; ++i) ink[i] = d_[i] >= t_;
        closed_ = close_ink(ink, w_, h_, gap);
        const std::vector<char>& closed = closed_;
        cm::flood_from_border(w_, h_, bg_, [&](int p) { return !closed[std::size_t(p)]; });
        if (gap > 0) give_back_barrier_rim(ink, bg_);
    }

    // The barrier's rim outside the ink touching `from` goes back to the background (see
    // give_back_barrier_rim).
    void give_back_barrier_rim(const std::vector<char>& ink, const std::vector<char>& from) {
        cm::give_back_barrier_rim(bg_, ink, closed_, from, w_, h_);
    }

    // Background-coloured regions the object encloses: holes through a filled drawing, or
    // the blank inside of a line drawing. A drawing whose ink covers less than its enclosed
    // blank regions is a line drawing. Which regions are holes is decided by evidence (see
    // judge_filled_regions, judge_line_regions) under `auto`; `fill` opens none, `keep`
    // every region of a filled drawing and the nested ones of a line drawing. The holes
    // become background.
    void open_holes(const std::string& mode, const std::vector<std::pair<int, int>>& at, SilhouetteResult& res) {
        std::vector<char> enclosed(n_, 0);
        std::size_t ink = 0;
        for (std::size_t i = 0; i < n_; ++i) {
            enclosed[i] = !bg_[i] && d_[i] < t_;
            ink += !bg_[i] && d_[i] >= t_;
        }
        std::vector<int> lab;
        std::vector<std::size_t> sizes;
        int nreg = mask_components(enclosed, w_, h_, false, lab, sizes);
        // Under `auto`, enclosed regions under kStrokeGapArea are gaps between strokes, not
        // holes; `keep` keeps every enclosed region, however small.
        const std::size_t min_hole = mode == "keep" ? 1 : kStrokeGapArea;
        std::size_t blank = 0;
        for (auto s : sizes) blank += s >= min_hole ? s : 0;
        line_drawing_ = ink <= blank;
        // Line art: the slits drawn between parts that the gap closing shut are outside.
        if (line_drawing_ && (res.slits_opened = open_drawn_slits(bg_, ink_mask(), closed_, w_, h_)) != 0) {
            for (std::size_t i = 0; i < n_; ++i) enclosed[i] = !bg_[i] && d_[i] < t_;
            nreg = mask_components(enclosed, w_, h_, false, lab, sizes);
        }
        if (mode != "fill" && line_drawing_) return open_nested_holes(mode, at, res);
        std::vector<char> dark;
        const std::vector<float> lum = luminance(dark);
        const RegionEvidence ev{&lab, nreg, &sizes, &bg_, &d_, &lum, &dark, t_, w_, h_};
        std::vector<EnclosedRegion> regions;
        if (mode == "auto") regions = judge_filled_regions(ev, min_hole);
        else regions = judge_all_regions(ev, mode == "keep", mode == "keep" ? "holes: keep" : "holes: fill");
        record(regions, lab, nullptr, res);
    }

    // The holes of a line drawing: blank regions behind an even number of strokes (see
    // nested_holes) are candidates, opened under `keep` or where `at` says (the openings the
    // opposite view confirmed); their barrier rim goes back to them.
    void open_nested_holes(const std::string& mode, const std::vector<std::pair<int, int>>& at, SilhouetteResult& res) {
        std::vector<char> blank(n_, 0), ink(n_, 0);
        for (std::size_t i = 0; i < n_; ++i) {
            blank[i] = !bg_[i] && !closed_[i];
            ink[i] = d_[i] >= t_;
        }
        std::vector<int> lab;
        std::vector<std::size_t> sizes;
        const int nreg = mask_components(blank, w_, h_, false, lab, sizes);
        const std::vector<char> nested = nested_holes(lab, nreg, closed_, bg_, w_, h_);
        std::vector<char> dark;
        const std::vector<float> lum = luminance(dark);
        const RegionEvidence ev{&lab, nreg, &sizes, &bg_, &d_, &lum, &dark, t_, w_, h_};
        std::vector<EnclosedRegion> regions = judge_line_regions(ev, nested, kStrokeGapArea, mode == "keep");
        if (mode == "keep") { // `keep` opens the daylight, not the parts seen through it
            const std::vector<char> parts = parts_seen_through(lab, nreg, nested, closed_, bg_, w_, h_);
            for (std::size_t r = 0; r < regions.size(); ++r)
                if (parts[r] && regions[r].hole) {
                    regions[r].hole = false;
                    regions[r].why = "line art, a part seen through an opening";
                }
        }
        open_regions_at(regions, lab, w_, h_, bgc_.ox, bgc_.oy, at);
        record(std::move(regions), lab, &ink, res);
    }

    // The judged regions into `res` and the background (holes opened; with `ink`, their
    // barrier rim too).
    void record(std::vector<EnclosedRegion> regions, const std::vector<int>& lab, const std::vector<char>* ink,
                SilhouetteResult& res) {
        std::vector<char> hole(n_, 0);
        bool any = false;
        for (std::size_t i = 0; i < n_; ++i)
            if (lab[i] >= 0 && regions[std::size_t(lab[i])].hole) {
                hole[i] = bg_[i] = 1;
                any = true;
            }
        for (const EnclosedRegion& g : regions) (g.hole ? res.holes_kept : res.regions_filled)++;
        // The closed candidates' and witnesses' pixels, for the opposite view to confirm (see
        // open_confirmed_holes); in this image's indices, moved to the whole image's later.
        for (std::size_t i = 0; i < n_; ++i)
            if (lab[i] >= 0) {
                EnclosedRegion& g = regions[std::size_t(lab[i])];
                if ((g.candidate || g.witness) && !g.hole) g.pixels.push_back(std::uint32_t(i));
            }
        if (any && ink) {
            std::vector<char> opened(regions.size(), 0), judged(regions.size(), 0);
            for (std::size_t r = 0; r < regions.size(); ++r) {
                opened[r] = regions[r].hole;
                judged[r] = regions[r].candidate || regions[r].witness;
            }
            open_hole_tips(bg_, *ink, closed_, lab, opened, judged, w_, h_);
            give_back_barrier_rim(*ink, hole);
        }
        res.regions = std::move(regions);
    }

    // Each pixel's luminance (Rec. 709 weights); `ink` gets the black and grey ink: under a
    // 0.45 of the paper's luminance (the background field's) and nearly colourless.
    std::vector<float> luminance(std::vector<char>& ink) const {
        std::vector<float> lum(n_);
        ink.assign(n_, 0);
        for (std::size_t i = 0; i < n_; ++i) {
            const auto p = img_.rgba(i);
            const Rgb b = bgc_.at(i);
            lum[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
            const double paper = 0.2126 * b[0] + 0.7152 * b[1] + 0.0722 * b[2];
            const float chroma = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
            ink[i] = lum[i] < 0.45 * paper && chroma < 0.15f;
        }
        return lum;
    }

    // A photograph (see segment_photo): the background is all but the object it finds.
    PhotoCut segment_as_photo(double noise, int backgrounds, const std::string& holes, double close_gaps) {
        PhotoCut cut = segment_photo(img_, d_, source_, backgrounds, t_, noise, holes, close_gaps);
        for (std::size_t i = 0; i < n_; ++i) bg_[i] = !cut.object[i];
        return cut;
    }

    // Overshooting strokes of a line drawing (see remove_thin_spurs).
    std::size_t remove_spurs(double gap) {
        if (!line_drawing_) return 0;
        std::vector<char> ink(n_);
        for (std::size_t i = 0; i < n_; ++i) ink[i] = d_[i] >= t_;
        const std::vector<char> before = bg_;
        const std::size_t removed = remove_thin_spurs(bg_, ink, w_, h_, gap);
        mark_forced(before);
        return removed;
    }

    // Line art's outline at its strokes' centre line (see pull_to_stroke_centre; thin lines:
    // place_thin_outline).
    void pull_to_stroke_centre(std::vector<float>& cov, SilhouetteResult& res) const {
        if (!line_drawing_) return;
        std::vector<char> ink(n_);
        for (std::size_t i = 0; i < n_; ++i) ink[i] = d_[i] >= t_;
        const std::vector<float> before = cov;
        res.stroke = cm::pull_to_stroke_centre(cov, bg_, ink, res.close_gaps, w_, h_);
        place_thin_outline(cov, bg_, d_, t_, w_, h_, res.stroke);
        res.stroke.paper_given_back = give_back_enclosed_paper(cov, before, bg_, w_, h_);
    }

    // A ground shadow under the object is background (see remove_ground_shadow).
    std::size_t remove_shadow() {
        const std::vector<char> before = bg_;
        const std::size_t removed = remove_ground_shadow(img_, bgc_, bg_);
        mark_forced(before);
        return removed;
    }

    // Pixels made background against their colour (spurs, shadow) stay outside whatever
    // their colour mix says.
    void mark_forced(const std::vector<char>& before) {
        if (forced_.empty()) forced_.assign(n_, 0);
        for (std::size_t i = 0; i < n_; ++i) forced_[i] = forced_[i] || (bg_[i] && !before[i]);
    }

    // Coverage: 1 inside, 0 outside; along the boundary the pixel is read as a mix of the
    // background and the nearest interior object colour, which keeps anti-aliasing.
    void coverage(std::vector<float>& cov) const {
        const std::vector<char> edge = boundary();
        tbb::parallel_for(0, h_, [&](int y) {
            for (int x = 0; x < w_; ++x) {
                const std::size_t i = std::size_t(y) * w_ + x;
                cov[i] = edge[i] ? boundary_coverage(x, y, edge) : (bg_[i] ? 0.0f : 1.0f);
                if (!forced_.empty() && forced_[i]) cov[i] = std::min(cov[i], 0.49f);
            }
        });
    }

private:
    // The ink: pixels at least the threshold from the background.
    std::vector<char> ink_mask() const {
        std::vector<char> ink(n_);
        for (std::size_t i = 0; i < n_; ++i) ink[i] = d_[i] >= t_;
        return ink;
    }

    // The pixels with a neighbour (8-connected) on the other side of the background's edge.
    std::vector<char> boundary() const {
        const int w = w_, h = h_;
        std::vector<char> edge(n_, 0);
        tbb::parallel_for(0, h, [&](int y) {
            const char* row = bg_.data() + std::size_t(y) * w;
            const bool inner_row = y > 0 && y + 1 < h;
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (inner_row && x > 0 && x + 1 < w) {
                    // Away from the frame: the eight neighbours without bounds checks.
                    const char c = row[x], *up = row - w, *down = row + w;
                    edge[i] = up[x - 1] != c || up[x] != c || up[x + 1] != c || row[x - 1] != c || row[x + 1] != c ||
                              down[x - 1] != c || down[x] != c || down[x + 1] != c;
                    continue;
                }
                for (int dy = -1; dy <= 1 && !edge[i]; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                        if (bg_[std::size_t(yy) * w + xx] != bg_[i]) {
                            edge[i] = 1;
                            break;
                        }
                    }
            }
        });
        return edge;
    }

    // The coverage of boundary pixel (x, y).
    float boundary_coverage(int x, int y, const std::vector<char>& edge) const {
        const int w = w_, h = h_;
        const std::size_t n = n_;
        const std::size_t i = std::size_t(y) * w + x;
        // Object colour: the nearest interior object pixel within 2 px, else the most
        // distinct object pixel there.
        std::size_t best = n, strongest = n;
        int best_r2 = 1 << 30;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::size_t j = std::size_t(yy) * w + xx;
                if (bg_[j]) continue;
                if (strongest == n || d_[j] > d_[strongest]) strongest = j;
                const int r2 = dx * dx + dy * dy;
                if (!edge[j] && (r2 < best_r2 || (r2 == best_r2 && d_[j] > d_[best]))) {
                    best = j;
                    best_r2 = r2;
                }
            }
        const std::size_t o = best != n ? best : strongest;
        const bool object = !bg_[i];
        if (o == n) return object ? 1.0f : 0.0f;
        const auto p = img_.rgba(i);
        const auto q = img_.rgba(o);
        const Rgb b = bgc_.at(i);
        double num = 0, den = 0;
        for (int k = 0; k < 3; ++k) {
            num += (p[k] - b[k]) * (q[k] - b[k]);
            den += (q[k] - b[k]) * (q[k] - b[k]);
        }
        const double alpha = den > 0 ? std::clamp(num / den, 0.0, 1.0) : (object ? 1.0 : 0.0);
        if (std::sqrt(den / 3.0) >= 2.0 * t_) return float(alpha); // clear contrast: the mix decides
        return float(object ? std::max(alpha, 0.5) : std::min(alpha, 0.49));
    }

    const Image& img_;
    const int w_, h_;
    const std::size_t n_;
    const double t_;
    BackgroundField bgc_;               ///< the background colour of each pixel
    std::vector<double> d_;             ///< each pixel's colour distance to it
    std::vector<unsigned char> source_; ///< which background: 0 the border's field, k + 1 the k-th further colour
    std::vector<char> bg_;              ///< background pixels
    bool line_drawing_ = false;
    std::vector<char> closed_; ///< the ink with its gaps closed (see close_ink)
    std::vector<char> forced_; ///< background against its colour (spurs, shadow); empty: none
};

// A window of an image: the rectangle sheets cut their panels by (sheet.h).
using Window = SheetPanel;

// The coverage of a drawing without meaningful alpha, from its background colour: into
// `whole` (the image's size, zero on entry) when the whole image was analysed, and returns
// nothing; or the window's coverage into `part` (zero beyond the window), and returns the
// window.
std::optional<Window> coverage_from_background(const Image& img, const SilhouetteOptions& opt, SilhouetteResult& res,
                                               std::vector<float>& whole, std::vector<float>& part) {
    res.method = "background";
    BackgroundModel model;
    double noise = 0;
    std::vector<Rgb> outliers;
    std::size_t total = 0;
    background_from_border(img, opt.background, model, noise, outliers, total);
    res.noise = noise;
    const double t = opt.threshold > 0 ? opt.threshold : std::clamp(0.1 + 5.0 * noise, 0.1, 0.5);
    res.threshold = t;
    const double weak = opt.threshold > 0 ? t : weak_ink_threshold(t, noise);
    std::vector<BorderCluster> more;
    if (opt.background == "auto") more = cluster_border(outliers, total, t, model.at(0, 0));
    res.border_colours = 1 + int(more.size());
    if (opt.photo == "on") {
        BackgroundCut cut(img, model, t, more);
        // A photograph: no gap closing unless asked for (its outline is not drawn).
        res.photo = true;
        res.close_gaps = std::max(0.0, opt.close_gaps);
        const PhotoCut photo = cut.segment_as_photo(noise, res.border_colours, opt.holes, res.close_gaps);
        res.weak_threshold = photo.weak_threshold;
        res.grown = photo.grown;
        res.holes_kept = photo.holes_kept;
        res.regions_filled = photo.holes_filled;
        if (opt.shadow == "auto") res.shadow_removed = cut.remove_shadow();
        whole.assign(std::size_t(img.width) * img.height, 0.0f);
        cut.coverage(whole);
        res.analysed_pixels = std::size_t(img.width) * img.height;
        return std::nullopt;
    }
    res.close_gaps = opt.close_gaps >= 0 ? opt.close_gaps : default_close_gaps(img.width, img.height);
    auto analyse = [&](BackgroundCut& cut, std::vector<float>& coverage) {
        res.weak_threshold = weak;
        res.weak_ink = cut.raise_weak_ink(weak);
        cut.flood_from_border(res.close_gaps);
        if (opt.shadow == "auto") res.shadow_removed = cut.remove_shadow();
        cut.open_holes(opt.holes, opt.open_at, res);
        res.spurs_removed = cut.remove_spurs(res.close_gaps);
        cut.coverage(coverage);
        cut.pull_to_stroke_centre(coverage, res);
    };
    // On the window around the ink when it is at most half the image (further backgrounds
    // along the border reach in from it: those drawings are analysed whole). The margin is
    // twice the gap closing's reach (its padding included) and eight pixels more.
    if (more.empty() && opt.window) {
        const int reach = int(std::ceil(0.5 * res.close_gaps + 1.0)) + 1;
        const std::optional<Window> win = ink_window(img, model, t, 2 * reach + 8);
        if (win && 2.0 * double(win->width) * win->height <= double(img.width) * img.height) {
            const Image window = crop_image(img, *win);
            BackgroundCut cut(window, model, t, more, win->x0, win->y0, img.width, img.height);
            part.assign(std::size_t(win->width) * win->height, 0.0f);
            analyse(cut, part);
            res.analysed_pixels = part.size();
            for (EnclosedRegion& g : res.regions) {
                g.x += win->x0;
                g.y += win->y0;
                for (std::uint32_t& p : g.pixels)
                    p = std::uint32_t((p / std::uint32_t(win->width) + std::uint32_t(win->y0)) *
                                          std::uint32_t(img.width) +
                                      p % std::uint32_t(win->width) + std::uint32_t(win->x0));
            }
            return win;
        }
    }
    BackgroundCut cut(img, model, t, more);
    whole.assign(std::size_t(img.width) * img.height, 0.0f);
    analyse(cut, whole);
    res.analysed_pixels = std::size_t(img.width) * img.height;
    return std::nullopt;
}

} // namespace

SilhouetteResult extract_silhouette(const Image& img, const ImageInfo& info, const SilhouetteOptions& opt) {
    check_background_option(opt.background);
    if (opt.keep != "auto" && opt.keep != "largest" && opt.keep != "all")
        throw Error("keep must be auto, largest or all, got \"" + opt.keep + "\"");
    if (opt.holes != "auto" && opt.holes != "fill" && opt.holes != "keep")
        throw Error("holes must be auto, fill or keep, got \"" + opt.holes + "\"");
    if (opt.shadow != "auto" && opt.shadow != "keep")
        throw Error("shadow must be auto or keep, got \"" + opt.shadow + "\"");
    if (opt.photo != "auto" && opt.photo != "on" && opt.photo != "off")
        throw Error("photo must be auto, on or off, got \"" + opt.photo + "\"");
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    if (w <= 0 || h <= 0 || img.channels < 1 || img.channels > 4 || img.samples() != n * std::size_t(img.channels))
        throw Error("the image is empty or not grey, RGB or RGBA");
    SilhouetteResult res;

    bool use_alpha = opt.background == "alpha";
    if (use_alpha && !info.has_alpha) throw Error("background: alpha, but the image has no alpha channel");
    if (opt.background == "auto" && info.has_alpha) {
        // Alpha is meaningful when it separates something: some pixels transparent, some opaque.
        std::size_t transparent = 0;
        for (std::size_t i = 0; i < n; ++i) transparent += img.rgba(i)[3] < 0.5f;
        use_alpha = transparent > 0 && transparent < n;
    }
    std::optional<Window> win;
    std::vector<float> whole; // the image's coverage, when the whole image was analysed
    std::vector<float> part;  // the window's coverage, when only the window was analysed
    if (use_alpha) {
        res.method = "alpha";
        whole.resize(n);
        for (std::size_t i = 0; i < n; ++i) whole[i] = std::clamp(img.rgba(i)[3], 0.0f, 1.0f);
        res.analysed_pixels = n;
    } else {
        win = coverage_from_background(img, opt, res, whole, part);
    }
    if (!win) {
        keep_components(w, h, opt.keep, whole, res);
        res.coverage = Coverage::of_window(std::move(whole), w, h, 0, 0, w, h);
        return res;
    }
    // Beyond the window the coverage is zero: the components are the window's, and the
    // window is what is kept (the box of its nonzero values).
    keep_components(win->width, win->height, opt.keep, part, res);
    res.coverage = Coverage::of_window(std::move(part), w, h, win->x0, win->y0, win->width, win->height);
    return res;
}

} // namespace cm
