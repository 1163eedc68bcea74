#include "photo.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "gaps.h"
#include "geometry/distance_transform.h"
#include "min_cut.h"
#include "pixel_flood.h"

namespace cm {

namespace {

using Chroma = std::array<double, 2>;

// A colour's chromaticity (R and G over R + G + B); `sum` gets R + G + B.
Chroma chroma(const float* p, double& sum) {
    sum = double(p[0]) + p[1] + p[2];
    if (sum <= 0) return {1.0 / 3, 1.0 / 3};
    return {p[0] / sum, p[1] / sum};
}

double squared(const Chroma& a, const Chroma& b) {
    const double x = a[0] - b[0], y = a[1] - b[1];
    return x * x + y * y;
}

// A chromaticity distribution: per-coordinate median, and the larger per-coordinate MAD
// spread as a variance; invalid with fewer than 50 samples.
struct ChromaModel {
    Chroma mean{};
    double var = 0;
    bool valid = false;
};

double median_of(std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

ChromaModel fit_chroma(const std::vector<Chroma>& s) {
    ChromaModel m;
    if (s.size() < 50) return m;
    double spread = 0;
    for (std::size_t k = 0; k < 2; ++k) {
        std::vector<double> c(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) c[i] = s[i][k];
        m.mean[k] = median_of(c);
        for (double& x : c) x = std::abs(x - m.mean[k]);
        spread = std::max(spread, 1.4826 * median_of(c));
    }
    m.var = std::max(spread * spread, 1e-5);
    m.valid = true;
    return m;
}

// The inputs every step reads.
struct Frame {
    const Image& img;
    const std::vector<double>& dist;
    const std::vector<unsigned char>& source;
    int w, h;
    std::size_t n, backdrops;
    double t;
    double pixel_noise; ///< per channel: the border's noise, at least one 8-bit step
    double min_sum;     ///< R + G + B a chromaticity needs to hold: 50 x the pixel noise
};

// Seeds (`seed`), and the seed components of at least 5 % of the largest (`grows`).
std::size_t find_seeds(const Frame& f, std::vector<char>& seed, std::vector<char>& grows) {
    seed.assign(f.n, 0);
    grows.assign(f.n, 0);
    for (std::size_t i = 0; i < f.n; ++i) seed[i] = f.dist[i] >= f.t;
    std::vector<char> taken(f.n, 0);
    std::vector<std::vector<int>> pieces;
    std::size_t largest = 0, count = 0;
    for (std::size_t s = 0; s < f.n; ++s) {
        if (!seed[s] || taken[s]) continue;
        taken[s] = 1;
        pieces.emplace_back();
        std::vector<int>& piece = pieces.back();
        grow_piece_8(
            int(s), f.w, f.h,
            [&](int q) {
                if (!seed[std::size_t(q)] || taken[std::size_t(q)]) return false;
                taken[std::size_t(q)] = 1;
                return true;
            },
            [&](int p) { piece.push_back(p); });
        largest = std::max(largest, piece.size());
        count += piece.size();
    }
    for (const auto& piece : pieces)
        if (double(piece.size()) >= 0.05 * double(largest))
            for (int p : piece) grows[std::size_t(p)] = 1;
    return count;
}

// Per backdrop: three times the 90th percentile of its border pixels' distances, within
// [t / 4, t / 2].
std::vector<double> weak_thresholds(const Frame& f) {
    std::vector<std::vector<double>> border(f.backdrops);
    auto sample = [&](std::size_t i) {
        if (f.dist[i] < f.t) border[f.source[i]].push_back(f.dist[i]);
    };
    for (int x = 0; x < f.w; ++x) {
        sample(std::size_t(x));
        sample(std::size_t(f.h - 1) * f.w + x);
    }
    for (int y = 1; y + 1 < f.h; ++y) {
        sample(std::size_t(y) * f.w);
        sample(std::size_t(y) * f.w + f.w - 1);
    }
    std::vector<double> tw(f.backdrops, 0.25 * f.t);
    for (std::size_t k = 0; k < f.backdrops; ++k) {
        std::vector<double>& b = border[k];
        if (b.empty()) continue;
        std::nth_element(b.begin(), b.begin() + std::ptrdiff_t(b.size() * 9 / 10), b.end());
        tw[k] = std::clamp(3.0 * b[b.size() * 9 / 10], 0.25 * f.t, 0.5 * f.t);
    }
    return tw;
}

struct ColourModels {
    ChromaModel object;
    std::vector<ChromaModel> backdrop; ///< per backdrop
};

// The object's chromaticity from the seeds' interior; each backdrop's from its pixels away
// from the seeds (beyond 3 % of the larger side: a shadow on the object lies nearer its lit
// parts). Only pixels bright enough for their chromaticity to hold count.
ColourModels fit_models(const Frame& f, const std::vector<char>& seed, const std::vector<char>& grows) {
    const std::vector<float> to_seed = squared_edt(grows, f.w, f.h);
    const double away = std::max(8.0, 0.03 * std::max(f.w, f.h));
    std::vector<Chroma> fg;
    std::vector<std::vector<std::pair<double, Chroma>>> bg(f.backdrops); // (R + G + B, chromaticity)
    const std::size_t w = std::size_t(f.w);
    for (int y = 1; y + 1 < f.h; ++y)
        for (int x = 1; x + 1 < f.w; ++x) {
            const std::size_t i = std::size_t(y) * w + std::size_t(x);
            double sum = 0;
            const Chroma c = chroma(f.img.rgba(i).data(), sum);
            if (grows[i] && grows[i - 1] && grows[i + 1] && grows[i - w] && grows[i + w]) {
                if (sum >= f.min_sum) fg.push_back(c);
            } else if (!seed[i] && to_seed[i] > float(away * away) && sum >= 0.2 * f.min_sum) {
                bg[f.source[i]].push_back({sum, c});
            }
        }
    ColourModels m;
    m.object = fit_chroma(fg);
    // A dark backdrop's chromaticity from its brightest pixels: R + G + B at least the
    // 90th percentile's when fewer reach 50 x the noise (at least 10 x the noise).
    for (auto& s : bg) {
        std::vector<Chroma> c;
        if (!s.empty()) {
            std::nth_element(s.begin(), s.begin() + std::ptrdiff_t(s.size() * 9 / 10), s.end(),
                             [](const auto& a, const auto& b) { return a.first < b.first; });
            const double bar = std::min(f.min_sum, s[s.size() * 9 / 10].first);
            for (const auto& [sum, chroma] : s)
                if (sum >= bar) c.push_back(chroma);
        }
        m.backdrop.push_back(fit_chroma(c));
    }
    return m;
}

// The region growth may reach: seeds, and pixels at least the weak threshold from their
// backdrop, 8-connected to growing seeds through such pixels.
std::vector<char> growth_region(const Frame& f, const std::vector<char>& seed, const std::vector<char>& grows,
                                const std::vector<double>& tw) {
    std::vector<char> region(f.n, 0);
    for (std::size_t s = 0; s < f.n; ++s) {
        if (!grows[s] || region[s]) continue;
        region[s] = 1;
        grow_piece_8(
            int(s), f.w, f.h,
            [&](int q) {
                const std::size_t j = std::size_t(q);
                if (region[j] || !(seed[j] || f.dist[j] >= tw[f.source[j]])) return false;
                region[j] = 1;
                return true;
            },
            [](int) {});
    }
    return region;
}

// A pixel's evidence for the object over its backdrop, within +-4: the difference of its
// squared chromaticity distances to the two models over twice their common variance (the
// larger of the two, widened by the noise of a ratio of small numbers); 0 when too dark to
// tell, +1 (growth as plain hysteresis) without the models.
double colour_evidence(const Frame& f, const ColourModels& m, std::size_t i) {
    const ChromaModel& b = m.backdrop[f.source[i]];
    if (!m.object.valid || !b.valid) return 1.0;
    double sum = 0;
    const Chroma c = chroma(f.img.rgba(i).data(), sum);
    if (sum < f.min_sum) return 0.0;
    const double var = std::max(m.object.var, b.var) + f.pixel_noise * f.pixel_noise / (sum * sum);
    return std::clamp((squared(c, b.mean) - squared(c, m.object.mean)) / (2 * var), -4.0, 4.0);
}

// The object's rim among the backdrop-coloured seeds: a band of them joined to the object's
// own seeds along its length, as much as it borders what is not a seed, and thin (no pixel
// deeper than kRimDepth from a pixel kept). A fold of cloth is lit along its middle and
// borders darker cloth on both sides, the object at its ends at most; a wall seen between
// two parts is joined to them all round but wide. Returns 1 for each pixel of such a band.
constexpr double kRimDepth = 4.0, kRimJoined = 0.5;
std::vector<char> rim_bands(const Frame& f, const std::vector<char>& seed, const std::vector<char>& candidate,
                            const std::vector<char>& keep, const std::vector<float>& inside) {
    std::vector<char> rim(f.n, 0), taken(f.n, 0);
    std::vector<int> band;
    for (std::size_t s = 0; s < f.n; ++s) {
        if (!candidate[s] || taken[s]) continue;
        band.clear();
        taken[s] = 1;
        std::size_t joined = 0, open = 0;
        bool thick = false;
        grow_piece_8(
            int(s), f.w, f.h,
            [&](int q) {
                if (!candidate[std::size_t(q)] || taken[std::size_t(q)]) return false;
                taken[std::size_t(q)] = 1;
                return true;
            },
            [&](int p) {
                band.push_back(p);
                const std::size_t i = std::size_t(p);
                const int x = p % f.w, y = p / f.w;
                bool to_object = false, to_open = false;
                const int next[4] = {x > 0 ? p - 1 : -1, x + 1 < f.w ? p + 1 : -1, y > 0 ? p - f.w : -1,
                                     y + 1 < f.h ? p + f.w : -1};
                for (int q : next) {
                    if (q < 0) continue;
                    const std::size_t j = std::size_t(q);
                    to_object = to_object || (seed[j] && keep[j]);
                    to_open = to_open || !seed[j];
                }
                joined += to_object ? 1 : 0;
                open += to_open ? 1 : 0;
                thick = thick || inside[i] > float(kRimDepth * kRimDepth);
            });
        if (!thick && double(joined) >= kRimJoined * double(open))
            for (int p : band) rim[std::size_t(p)] = 1;
    }
    return rim;
}

// Seeds whose colour is clearly a backdrop's (a fold of a dark cloth catching the light, a
// wall beside the cloth, far from the backdrop the border's field gives them but of its
// chromaticity, not the object's): not seeds; the cut decides them with the other weak
// pixels. The object's model comes from the largest seed components, so this holds for
// what differs from most of the object; its rim (a seed beside one of the object's colour)
// stays. Returns the pixels demoted.
constexpr double kBackdropEvidence = -2.0, kRim = 1.5, kBand = 3.0;
std::size_t demote_backdrop_seeds(const Frame& f, const ColourModels& m, std::vector<char>& seed,
                                  std::vector<char>& grows) {
    std::vector<float> evidence(f.n, 0.0f);
    for (std::size_t i = 0; i < f.n; ++i)
        if (seed[i]) evidence[i] = float(colour_evidence(f, m, i));
    // The object's rim mixes its colour with the backdrop's: a pixel beside (within kRim px of) a seed
    // of the object's colour stays.
    std::vector<char> object_coloured(f.n);
    for (std::size_t i = 0; i < f.n; ++i) object_coloured[i] = seed[i] && evidence[i] > 0;
    const std::vector<float> to_object = squared_edt(object_coloured, f.w, f.h);
    auto beside_object = [&](std::size_t i) { return to_object[i] <= float(kRim * kRim); };
    std::vector<int> comp(f.n, -1);
    std::vector<float> median;
    std::vector<char> at_border;
    for (std::size_t s0 = 0; s0 < f.n; ++s0) {
        if (!seed[s0] || comp[s0] >= 0) continue;
        const int id = int(median.size());
        std::vector<float> ev;
        bool border = false;
        comp[s0] = id;
        grow_piece_8(
            int(s0), f.w, f.h,
            [&](int q) {
                if (!seed[std::size_t(q)] || comp[std::size_t(q)] >= 0) return false;
                comp[std::size_t(q)] = id;
                return true;
            },
            [&](int p) {
                ev.push_back(evidence[std::size_t(p)]);
                const int x = p % f.w, y = p / f.w;
                border = border || x == 0 || y == 0 || x + 1 == f.w || y + 1 == f.h;
            });
        at_border.push_back(border);
        std::nth_element(ev.begin(), ev.begin() + std::ptrdiff_t(ev.size() / 2), ev.end());
        median.push_back(ev.empty() ? 0.0f : ev[ev.size() / 2]);
    }
    // Demoted: in a component reaching the frame (a cloth hangs from it), all of it when most
    // of it is backdrop-coloured; else its backdrop-coloured pixels away from the object's own
    // colour where they make patches at least kBand px across (a fold, a wall: the opening of
    // those pixels by a disc of that diameter). A thinner band is the object's rim against the
    // backdrop (its shadowed underside, where it reaches the frame), its colours mixed, and
    // stays; so does a wider one that runs along the object (rim_bands: the blurred, fringed
    // edge of a dark part against a dark stand). Elsewhere a seed stays: a small dark piece of
    // the object may well look like the backdrop.
    std::vector<char> keep(f.n, 1), backdrop_piece(f.n, 0);
    for (std::size_t i = 0; i < f.n; ++i) {
        if (!seed[i] || evidence[i] > kBackdropEvidence || !at_border[std::size_t(comp[i])]) continue;
        backdrop_piece[i] = median[std::size_t(comp[i])] <= kBackdropEvidence / 2;
        keep[i] = !backdrop_piece[i] && beside_object(i);
    }
    const float r2 = float(kBand * kBand / 4);
    const std::vector<float> inside = squared_edt(keep, f.w, f.h); // to the nearest pixel kept
    std::vector<char> core(f.n, 0);
    for (std::size_t i = 0; i < f.n; ++i) core[i] = !keep[i] && inside[i] > r2;
    const std::vector<float> to_core = squared_edt(core, f.w, f.h);
    std::vector<char> candidate(f.n, 0);
    for (std::size_t i = 0; i < f.n; ++i) candidate[i] = seed[i] && !keep[i] && !backdrop_piece[i];
    const std::vector<char> rim = rim_bands(f, seed, candidate, keep, inside);
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < f.n; ++i)
        if (backdrop_piece[i] || (!keep[i] && !rim[i] && to_core[i] <= r2)) out.push_back(i);
    for (std::size_t i : out) seed[i] = grows[i] = 0;
    return out.size();
}

// Whether an enclosed region is a see-through gap rather than a shadow the object casts on
// itself: large (at least kGapShare of the object's area: a shadow pocket is small beside
// its object), and where at least a quarter of it is bright enough to tell, clearly of a
// backdrop's colour (mean evidence -1 or less), else mostly (60 %) as dark as a backdrop
// (under the weak threshold), with no evidence for the object.
constexpr double kGapShare = 0.03;
bool see_through(const Frame& f, const ColourModels& m, const std::vector<double>& tw, const std::vector<int>& hole,
                 std::size_t object_area) {
    std::size_t dark = 0, told = 0;
    double evidence = 0;
    for (int p : hole) {
        const std::size_t i = std::size_t(p);
        dark += f.dist[i] < tw[f.source[i]] ? 1 : 0;
        const double e = colour_evidence(f, m, i);
        if (e != 0.0) {
            evidence += e;
            ++told;
        }
    }
    if (double(hole.size()) < kGapShare * double(object_area)) return false;
    // Mostly bright enough to tell: a backdrop's colour, clearly.
    if (told >= 50 && double(told) >= 0.25 * double(hole.size())) return evidence < -1.0 * double(told);
    return double(dark) >= 0.6 * double(hole.size()) && evidence <= 0;
}

// Labels the region's weak pixels (object: 1 in `obj`) by a minimum cut of: per pixel its
// colour evidence, per pair of 8-neighbours labelled apart kSmooth over their distance;
// seeds are object, what lies outside the region backdrop. Returns the pixels made object.
constexpr double kSmooth = 4.0;
std::size_t cut_region(const Frame& f, const std::vector<char>& seed, const std::vector<char>& region,
                       const ColourModels& m, std::vector<char>& obj) {
    std::vector<int> node(f.n, -1);
    int nodes = 0;
    for (std::size_t i = 0; i < f.n; ++i)
        if (region[i] && !seed[i]) node[i] = nodes++;
    MinCut graph(nodes);
    const double diagonal = kSmooth / std::sqrt(2.0);
    for (int y = 0; y < f.h; ++y)
        for (int x = 0; x < f.w; ++x) {
            const std::size_t i = std::size_t(y) * f.w + x;
            if (node[i] < 0) continue;
            const double e = colour_evidence(f, m, i);
            double object_side = std::max(e, 0.0), backdrop_side = std::max(-e, 0.0);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= f.w || yy >= f.h) continue;
                    const std::size_t j = std::size_t(yy) * f.w + xx;
                    const double c = dx != 0 && dy != 0 ? diagonal : kSmooth;
                    if (node[j] >= 0) {
                        if (j > i) graph.add_edge(node[i], node[j], c, c); // each pair once
                    } else if (seed[j]) {
                        object_side += c; // apart from a seed if backdrop
                    } else {
                        backdrop_side += c; // apart from the fixed backdrop if object
                    }
                }
            graph.add_terminal(node[i], object_side, backdrop_side);
        }
    graph.solve();
    std::size_t grown = 0;
    for (std::size_t i = 0; i < f.n; ++i) {
        obj[i] = seed[i] || (node[i] >= 0 && graph.source_side(node[i]));
        grown += node[i] >= 0 && obj[i];
    }
    return grown;
}

// Each backdrop's colour again, from the weak pixels the cut gave it: the backdrop as it is
// at their brightness, next to the object (where present).
void refit_backdrops(const Frame& f, const std::vector<char>& seed, const std::vector<char>& region,
                     const std::vector<char>& obj, ColourModels& m) {
    std::vector<std::vector<Chroma>> bg(f.backdrops);
    for (std::size_t i = 0; i < f.n; ++i) {
        if (!region[i] || seed[i] || obj[i]) continue;
        double sum = 0;
        const Chroma c = chroma(f.img.rgba(i).data(), sum);
        if (sum >= f.min_sum) bg[f.source[i]].push_back(c);
    }
    for (std::size_t k = 0; k < f.backdrops; ++k) {
        const ChromaModel b = fit_chroma(bg[k]);
        if (b.valid) m.backdrop[k] = b;
    }
}

// What the border reaches through the rest is background (breaks up to close_gaps bridged;
// the barrier's rim outside the object goes back to it); regions the object encloses are
// filled unless `holes` is keep, or under auto they are see-through gaps (see_through).
// Counts them into `cut`.
void close_enclosed(const Frame& f, const ColourModels& m, const std::vector<double>& tw, const std::string& holes,
                    double close_gaps, PhotoCut& cut) {
    std::vector<char>& obj = cut.object;
    const std::size_t w = std::size_t(f.w);
    const std::vector<char> barrier = close_ink(obj, f.w, f.h, close_gaps);
    std::vector<char> reached(f.n, 0);
    flood_from_border(f.w, f.h, reached, [&](int p) { return !barrier[std::size_t(p)]; });
    std::vector<char> rim(f.n, 0);
    for (int y = 0; y < f.h; ++y)
        for (int x = 0; x < f.w; ++x) {
            const std::size_t i = std::size_t(y) * w + std::size_t(x);
            if (obj[i] || reached[i] || !barrier[i]) continue;
            rim[i] = (x > 0 && reached[i - 1]) || (x + 1 < f.w && reached[i + 1]) || (y > 0 && reached[i - w]) ||
                     (y + 1 < f.h && reached[i + w]);
        }
    for (std::size_t i = 0; i < f.n; ++i) reached[i] = reached[i] || rim[i];

    std::size_t object_area = 0;
    for (char o : obj) object_area += o ? 1 : 0;
    std::vector<char> seen(f.n, 0);
    std::vector<int> stack, hole;
    for (std::size_t s = 0; s < f.n; ++s) {
        if (obj[s] || reached[s] || seen[s]) continue;
        hole.clear();
        stack.push_back(int(s));
        seen[s] = 1;
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            hole.push_back(p);
            const int x = p % f.w, y = p / f.w;
            const int next[4] = {x > 0 ? p - 1 : -1, x + 1 < f.w ? p + 1 : -1, y > 0 ? p - f.w : -1,
                                 y + 1 < f.h ? p + f.w : -1};
            for (int q : next)
                if (q >= 0 && !obj[std::size_t(q)] && !reached[std::size_t(q)] && !seen[std::size_t(q)]) {
                    seen[std::size_t(q)] = 1;
                    stack.push_back(q);
                }
        }
        const bool fill = holes == "fill" || (holes != "keep" && !see_through(f, m, tw, hole, object_area));
        (fill ? cut.holes_filled : cut.holes_kept)++;
        if (fill)
            for (int p : hole) obj[std::size_t(p)] = 1;
    }
}

} // namespace

PhotoCut segment_photo(const Image& img, const std::vector<double>& dist, const std::vector<unsigned char>& source,
                       int backgrounds, double t, double noise, const std::string& holes, double close_gaps) {
    const double pixel_noise = std::max(noise, 1.0 / 255.0);
    const Frame f{img,
                  dist,
                  source,
                  img.width,
                  img.height,
                  std::size_t(img.width) * img.height,
                  std::size_t(std::max(1, backgrounds)),
                  t,
                  pixel_noise,
                  50.0 * pixel_noise};
    PhotoCut cut;
    cut.object.assign(f.n, 0);
    std::vector<char> seed, grows;
    cut.seeds = find_seeds(f, seed, grows);
    if (cut.seeds == 0) return cut;
    const std::vector<double> tw = weak_thresholds(f);
    cut.weak_threshold = tw[0];
    ColourModels models = fit_models(f, seed, grows);
    cut.demoted = demote_backdrop_seeds(f, models, seed, grows);
    const std::vector<char> region = growth_region(f, seed, grows, tw);
    // Two rounds: the second with the backdrops as the first cut found them.
    cut.grown = cut_region(f, seed, region, models, cut.object);
    refit_backdrops(f, seed, region, cut.object, models);
    cut.grown = cut_region(f, seed, region, models, cut.object);
    close_enclosed(f, models, tw, holes, close_gaps, cut);
    return cut;
}

} // namespace cm
