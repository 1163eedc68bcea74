// Exact Euclidean distance transform of a binary image (Felzenszwalb and Huttenlocher 2012).
#include "geometry/distance_transform.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "util/uninit_vector.h"

namespace cm {

namespace {

// 1D squared distance transform of f (Felzenszwalb and Huttenlocher 2012) into d.
void edt_1d(const float* f, float* d, int n, int* v, float* z) {
    int k = 0;
    v[0] = 0;
    z[0] = -std::numeric_limits<float>::infinity();
    z[1] = std::numeric_limits<float>::infinity();
    auto meet = [&](int q, int p) {
        return ((f[q] + float(q) * float(q)) - (f[p] + float(p) * float(p))) / (2.0f * float(q - p));
    };
    for (int q = 1; q < n; ++q) {
        float s = meet(q, v[k]);
        while (s <= z[k]) {
            --k;
            s = meet(q, v[k]);
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = std::numeric_limits<float>::infinity();
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < float(q)) ++k;
        const float dq = float(q - v[k]);
        d[q] = dq * dq + f[v[k]];
    }
}

// The row pass of one row, over the part that changes: only the stretch from the first to the
// last pixel away from a seed changes, and only the seeds just beyond it can be nearest there
// (any seed farther out is farther from every pixel of the stretch): the transform of that
// stretch and its two neighbours gives the same values as the whole row's, and the rest stays
// 0. A silhouette's row of distances to the outside is the silhouette's width only.
class RowPass {
public:
    explicit RowPass(int w) : f_(std::size_t(w)), z_(std::size_t(w) + 1), v_(std::size_t(w)) {}
    // The pixels first..last (inclusive) are the row's first and last away from a seed; `column`
    // gives pixel x's value after the column pass; the stretch's values go to out[x].
    template <typename Column>
    void run(int w, int first, int last, Column&& column, float* out) {
        const int a = std::max(0, first - 1), b = std::min(w, last + 2);
        for (int x = a; x < b; ++x) f_[std::size_t(x - a)] = column(x);
        edt_1d(f_.data(), out + a, b - a, v_.data(), z_.data());
    }

private:
    std::vector<float> f_, z_;
    std::vector<int> v_;
};

// What squared_edt_signed() gives the outside pixels it does not work out.
constexpr float kNotWorkedOut = std::numeric_limits<float>::infinity();

// The column pass of squared_edt in place over g, by strips of columns. Along a column the
// input is only seed (0) or not (far), so its transform is the square of the distance to the
// nearest seed above or below: a sweep down the rows counts the distance to the seed above, a
// sweep up takes the nearer of that and the seed below. Both sweeps go along whole rows of a
// strip of columns (contiguous, vectorised), in place. Counts stay integers (exact in float);
// kEdtFar + 1 rounds back to kEdtFar, so a column without a seed ends at kEdtFar.
constexpr int kStrip = 256;

} // namespace

std::vector<float> squared_edt(const std::vector<char>& seed, int w, int h) { return squared_edt(seed.data(), w, h); }

std::vector<float> squared_edt(const char* seed, int w, int h) {
    std::vector<float> g(std::size_t(w) * h);
    // Columns, then rows. A row that is all seeds stays 0 and a line without any stays
    // kEdtFar (kEdtFar + n^2 rounds back to kEdtFar in float): both are skipped, which
    // for a silhouette is most of the image (its box is a fraction of the frame).
    const int strips = (w + kStrip - 1) / kStrip;
    tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> below(kStrip);
        for (int t = r.begin(); t != r.end(); ++t) {
            const int x0 = t * kStrip, nx = std::min(kStrip, w - x0);
            for (int y = 0; y < h; ++y) {
                const char* s = seed + std::size_t(y) * w + x0;
                float* row = g.data() + std::size_t(y) * w + x0;
                if (y == 0) {
                    for (int b = 0; b < nx; ++b) row[b] = s[b] ? 0.0f : kEdtFar;
                } else {
                    const float* above = row - w;
                    for (int b = 0; b < nx; ++b) row[b] = s[b] ? 0.0f : above[b] + 1.0f;
                }
            }
            std::fill_n(below.begin(), nx, kEdtFar);
            for (int y = h - 1; y >= 0; --y) {
                float* row = g.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) {
                    const float m = std::min(row[b], below[b] + 1.0f);
                    below[b] = m;
                    row[b] = m >= kEdtFar ? kEdtFar : m * m;
                }
            }
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        RowPass pass(w);
        for (int y = r.begin(); y != r.end(); ++y) {
            float* row = g.data() + std::size_t(y) * w;
            const auto nonzero = [](float x) { return x != 0.0f; };
            float* first = std::find_if(row, row + w, nonzero);
            if (first == row + w) continue; // all seeds
            float* last =
                std::find_if(std::make_reverse_iterator(row + w), std::make_reverse_iterator(first), nonzero).base();
            pass.run(
                w, int(first - row), int(last - row) - 1, [row](int x) { return row[x]; }, row);
        }
    });
    return g;
}

namespace {

// What a row pass of squared_edt_signed() needs of its own, kept per thread.
struct SignedRowScratch {
    SignedRowScratch(int w, int reach)
        : pass(w),
          for_in(std::size_t(w)),
          near(std::size_t(w) + 2 * std::size_t(reach)),
          band(std::size_t(w)),
          out(std::size_t(w)) {}
    RowPass pass;
    std::vector<float> for_in; ///< the inside pixels' values
    std::vector<float> near;   ///< the transform to the inside in the column, `reach` kEdtFar on each side
    std::vector<float> band;   ///< the outside pixels' values
    std::vector<float> out;
};

// One row of squared_edt_signed(): s is the row of the mask, col its values after the column
// pass (for each pixel, the squared distance to the nearest pixel of the other kind in its
// column). Inside pixels take the transform of the inside stretch (the other kind's pixels as
// seeds, as squared_edt() of the outside has it). An outside pixel's nearest inside pixel
// within `reach` lies in a column within `reach` whose own value (0 for an inside pixel) is
// at most reach^2: the smallest of dx^2 plus the value of the column dx away, over the columns
// within reach, is the pixel's value when it is at most reach^2. Worked out for the pixels
// within reach of such a column. The loops over pixels have no branch (the mask as 0 or 1,
// selects), so they are vectorised.
void signed_row(const unsigned char* s, const float* col, int w, int reach, SignedRowScratch& t) {
    const float r2 = float(reach) * float(reach);
    float* vin = t.near.data() + reach; // the transform to the inside in the column
    for (int x = 0; x < w; ++x) vin[x] = col[x] * float(1 - s[x]);
    int lo = 0, hi = w - 1; // the first and last column at most reach^2 away (none: lo > hi)
    while (lo < w && !(vin[lo] <= r2)) ++lo;
    while (hi >= lo && !(vin[hi] <= r2)) --hi;
    const int a = lo <= hi ? std::max(0, lo - reach) : w, b = std::min(w, hi + reach + 1); // worked out
    float* band = t.band.data();
    std::fill(band, band + std::min(a, w), kNotWorkedOut);
    if (a < b) {
        std::fill(vin - reach, vin, kEdtFar);
        std::fill(vin + w, vin + w + reach, kEdtFar);
        std::copy(vin + a, vin + b, band + a);
        for (int dx = 1; dx <= reach; ++dx) {
            const float dx2 = float(dx) * float(dx);
            for (int x = a; x < b; ++x) band[x] = std::min(band[x], std::min(vin[x - dx], vin[x + dx]) + dx2);
        }
        for (int x = a; x < b; ++x) band[x] = band[x] <= r2 ? band[x] : kNotWorkedOut;
    }
    std::fill(band + std::max(a, b), band + w, kNotWorkedOut);
    const void* first_in = std::memchr(s, 1, std::size_t(w));
    if (!first_in) {
        std::copy(band, band + w, t.out.data());
        return;
    }
    int last_in = w - 1;
    while (!s[last_in]) --last_in;
    t.pass.run(
        w, int(static_cast<const unsigned char*>(first_in) - s), last_in, [&](int x) { return col[x] * float(s[x]); },
        t.for_in.data());
    const float* for_in = t.for_in.data();
    float* out = t.out.data();
    for (int x = 0; x < w; ++x) out[x] = s[x] ? for_in[x] : band[x];
}

} // namespace

void squared_edt_signed(const char* inside, int w, int h, int reach,
                        const std::function<void(int, const float*)>& row) {
    const auto* mask = reinterpret_cast<const unsigned char*>(inside);
    // One column pass for both kinds: per pixel the count to the nearest pixel of the other
    // kind above it, then the nearer of that and the one below, as squared_edt's passes for
    // each kind's seeds give them (a pixel of one kind is a seed of the other's transform). The
    // counters of both kinds go along every column, one of them 0 (the pixel's own kind);
    // products with the mask (0 or 1, exact) keep the loops free of branches, so vectorised.
    UninitVector<float> column(std::size_t(w) * std::size_t(h));
    const int strips = (w + kStrip - 1) / kStrip;
    tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const tbb::blocked_range<int>& r) {
        float to_in[kStrip], to_out[kStrip]; // the count since the last inside, outside pixel
        for (int t = r.begin(); t != r.end(); ++t) {
            const int x0 = t * kStrip, nx = std::min(kStrip, w - x0);
            std::fill_n(to_in, nx, kEdtFar);
            std::fill_n(to_out, nx, kEdtFar);
            for (int y = 0; y < h; ++y) {
                const unsigned char* s = mask + std::size_t(y) * w + x0;
                float* g = column.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) {
                    const float in = float(s[b]);
                    to_in[b] = (to_in[b] + 1.0f) * (1.0f - in);
                    to_out[b] = (to_out[b] + 1.0f) * in;
                    g[b] = to_in[b] + to_out[b];
                }
            }
            std::fill_n(to_in, nx, kEdtFar);
            std::fill_n(to_out, nx, kEdtFar);
            for (int y = h - 1; y >= 0; --y) {
                const unsigned char* s = mask + std::size_t(y) * w + x0;
                float* g = column.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) {
                    const float in = float(s[b]);
                    const float m = std::min(g[b], to_out[b] * in + to_in[b] * (1.0f - in) + 1.0f);
                    to_out[b] = m * in;
                    to_in[b] = m * (1.0f - in);
                    g[b] = std::min(m * m, kEdtFar);
                }
            }
        }
    });
    tbb::enumerable_thread_specific<SignedRowScratch> scratch([w, reach] { return SignedRowScratch(w, reach); });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        SignedRowScratch& t = scratch.local();
        for (int y = r.begin(); y != r.end(); ++y) {
            signed_row(mask + std::size_t(y) * w, column.data() + std::size_t(y) * w, w, reach, t);
            row(y, t.out.data());
        }
    });
}

} // namespace cm
