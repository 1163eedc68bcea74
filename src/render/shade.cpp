#include "render/shade.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "render/raster.h"

namespace cm {

namespace {

// Deterministic noise in [0, 1) per pixel (splitmix64 of the coordinates).
double hash01(std::uint64_t x, std::uint64_t y, std::uint64_t seed) {
    std::uint64_t z = (x * 0x9E3779B97F4A7C15ull) ^ (y * 0xC2B2AE3D27D4EB4Full) ^ (seed * 0x165667B19E3779F9ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * (1.0 / 9007199254740992.0);
}

// Per pixel: whether its chamfer distance (1 along an axis, 1.4142 along a diagonal, in
// pixels) to the nearest pixel where `seed` is set is at most `t`; pixels outside the image
// count as seeds when `outside_seeds`. The distance to a seed dx, dy pixels away is
// (max - min) + 1.4142 min of |dx| and |dy|, which grows with |dx|: per row, the distance along
// it to its nearest seed (capped past t) settles the row, and only the rows within t can
// hold a seed near enough. Rows run in parallel.
std::vector<char> within_chamfer(const std::vector<char>& seed, int w, int h, bool outside_seeds, float t) {
    const int r = std::max(0, int(std::floor(t)));
    const int cap = r + 1; // farther along a row than r pixels is too far at any dy
    std::vector<std::int32_t> along(std::size_t(w) * h);
    tbb::parallel_for(0, h, [&](int y) {
        const char* s = seed.data() + std::size_t(y) * w;
        std::int32_t* d = along.data() + std::size_t(y) * w;
        const std::int32_t start = outside_seeds ? 0 : cap; // at the column beyond the image
        std::int32_t k = start;
        for (int x = 0; x < w; ++x) d[x] = k = s[x] ? 0 : std::min(cap, k + 1);
        k = start;
        for (int x = w - 1; x >= 0; --x) d[x] = std::min(d[x], k = s[x] ? 0 : std::min(cap, k + 1));
    });
    // Per |dy|: the largest distance along a row that is near enough (-1: none).
    std::vector<std::int32_t> reach(std::size_t(r) + 1, -1);
    for (int ady = 0; ady <= r; ++ady)
        for (int dx = 0; dx < cap; ++dx) {
            const int lo = std::min(dx, ady), hi = std::max(dx, ady);
            if (float(hi - lo) + 1.4142f * float(lo) <= t) reach[std::size_t(ady)] = dx;
        }
    std::vector<char> out(seed.size());
    tbb::parallel_for(0, h, [&](int y) {
        char* o = out.data() + std::size_t(y) * w;
        std::fill_n(o, w, 0);
        for (int dy = -r; dy <= r; ++dy) {
            const int yy = y + dy;
            const std::int32_t most = reach[std::size_t(std::abs(dy))];
            if (yy < -1 || yy > h || most < 0) continue;
            if (yy == -1 || yy == h) { // the row beyond the image: all seeds when they count
                if (outside_seeds) std::fill_n(o, w, 1);
                continue;
            }
            const std::int32_t* d = along.data() + std::size_t(yy) * w;
            for (int x = 0; x < w; ++x) o[x] |= char(d[x] <= most);
        }
    });
    return out;
}

double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

// What the phases of a drawing share: the mesh (with vertex normals), the caller's camera
// and the supersampled one (W x H samples) with its depth image, the face normals, and the
// empty samples. The depth image and the arrays of samples cover a window of the samples
// (D.x0, D.y0, w x h): every sample beyond it is empty paper.
struct ArtScene {
    const Mesh& mesh;
    const Camera& cam;
    const Camera& hi;
    const DepthImage& D;
    const int W, H, ss;
    std::vector<Vec3d> fnormal;
    std::vector<char> empty; ///< over the window
    int w() const { return D.width; }
    int h() const { return D.height; }
    /// The window's index of sample (x, y) of the picture; -1 beyond the window.
    std::ptrdiff_t at(int x, int y) const {
        const unsigned dx = unsigned(x - D.x0), dy = unsigned(y - D.y0);
        return dx < unsigned(D.width) && dy < unsigned(D.height) ? std::ptrdiff_t(dy) * D.width + std::ptrdiff_t(dx)
                                                                 : -1;
    }
};

std::vector<Vec3d> face_normals(const Mesh& mesh) {
    std::vector<Vec3d> fnormal(mesh.triangles.size());
    tbb::parallel_for(std::size_t(0), mesh.triangles.size(), [&](std::size_t t) {
        const auto& f = mesh.triangles[t];
        const Vec3d a(mesh.positions[f[0]]), b(mesh.positions[f[1]]), c(mesh.positions[f[2]]);
        fnormal[t] = normalize(cross(b - a, c - a));
    });
    return fnormal;
}

// Creases and inner contours: samples next to one of another face that turns by more than
// crease_deg or lies at another depth.
std::vector<char> crease_samples(const ArtScene& s, const ArtOptions& opt) {
    const int W = s.w(), H = s.h(); // the window (beyond it every sample is empty)
    const DepthImage& D = s.D;
    const Camera& cam = s.cam;
    std::vector<char> crease(std::size_t(W) * H, 0);
    const double cos_crease = std::cos(double(opt.crease_deg) * 3.14159265358979323846 / 180.0);
    const double jump = cam.orthographic() ? 6.0 / s.hi.scale : 0.0;
    auto depth_jump = [&](std::size_t i, std::size_t j) {
        const double a = D.depth[i], b = D.depth[j];
        return cam.orthographic() ? std::abs(a - b) > jump
                                  : std::abs(a - b) > 0.01 * std::max(std::abs(a), std::abs(b));
    };
    auto is_crease = [&](std::size_t i, std::size_t j) {
        return !s.empty[j] && D.face[j] != D.face[i] &&
               (dot(s.fnormal[D.face[i]], s.fnormal[D.face[j]]) < cos_crease || depth_jump(i, j));
    };
    // Each sample looks at its four neighbours and marks only itself, so rows can run in
    // parallel without two threads writing one sample. Of a crease pair the nearer side
    // carries the line; at equal depth the left (upper) one.
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            if (s.empty[i]) continue;
            const bool right = x + 1 < W && is_crease(i, i + 1) && !(D.depth[i + 1] < D.depth[i]);
            const bool down = y + 1 < H && is_crease(i, i + W) && !(D.depth[i + W] < D.depth[i]);
            const bool left = x > 0 && is_crease(i, i - 1) && D.depth[i] < D.depth[i - 1];
            const bool up = y > 0 && is_crease(i, i - W) && D.depth[i] < D.depth[i - W];
            crease[i] = char(right || down || left || up);
        }
    });
    return crease;
}

// The colour (RGB) of a sample: paper, ink on the lines, or the shaded fill. Made per sample
// as the picture averages them (no image of the samples' colours is held).
class SampleShader {
public:
    SampleShader(const ArtScene& s, const std::vector<char>& on_line, const ArtOptions& opt)
        : s_(s), on_line_(on_line), opt_(opt), d_(s.cam.d) {
        // Camera frame for the light: from the upper left, in front.
        Vec3d u = s.cam.u, r = s.cam.r;
        if (!s.cam.orthographic()) {
            const Vec3d up{0, 1, 0};
            r = normalize(cross(d_, up));
            if (length(r) < 0.5) r = {1, 0, 0};
            u = cross(r, d_);
        }
        light_ = normalize(d_ * -0.55 + u * 0.65 - r * 0.45);
    }
    /// The sample's colour into `out`; whether the mesh covers the sample.
    bool operator()(int x, int y, float out[3]) const {
        const int W = s_.W, H = s_.H;
        const Mesh& mesh = s_.mesh;
        const DepthImage& D = s_.D;
        const ArtOptions& opt = opt_;
        const std::ptrdiff_t at = s_.at(x, y);
        const std::size_t i = std::size_t(at);
        if (at < 0 || (s_.empty[i] && !(opt.lines && opt.outline_centred && on_line_[i]))) {
            // Paper with a mild vignette.
            const double uu = (x + 0.5) / W * 2 - 1, vv = (y + 0.5) / H * 2 - 1;
            const double v = 1.0 - opt.vignette * 0.5 * (uu * uu + vv * vv);
            for (int k = 0; k < 3; ++k) out[k] = float(opt.paper[std::size_t(k)] * v);
            return false;
        }
        if (opt.lines && on_line_[i]) {
            for (int k = 0; k < 3; ++k) out[k] = opt.ink[std::size_t(k)];
            return true;
        }
        if (!opt.shade) {
            for (int k = 0; k < 3; ++k) out[k] = opt.fill[std::size_t(k)];
            return true;
        }
        // Smooth normal at the pixel centre: barycentric coordinates of the ray's hit.
        const std::uint32_t t = D.face[i];
        const auto& f = mesh.triangles[t];
        const Vec3d a(mesh.positions[f[0]]), b(mesh.positions[f[1]]), c(mesh.positions[f[2]]);
        Vec3d o, dir;
        s_.hi.ray(x + 0.5, y + 0.5, o, dir);
        const Vec3d e1 = b - a, e2 = c - a, pv = cross(dir, e2);
        const double det = dot(e1, pv);
        Vec3d n = s_.fnormal[t];
        if (std::abs(det) > 1e-300) {
            const Vec3d tv = o - a;
            const double bu = std::clamp(dot(tv, pv) / det, 0.0, 1.0);
            const double bv = std::clamp(dot(dir, cross(tv, e1)) / det, 0.0, 1.0 - bu);
            const Vec3d sn = Vec3d(mesh.normals[f[0]]) * (1 - bu - bv) + Vec3d(mesh.normals[f[1]]) * bu +
                             Vec3d(mesh.normals[f[2]]) * bv;
            if (length(sn) > 1e-12) n = normalize(sn);
        }
        if (dot(n, d_) > 0) n = -n; // seen from behind (open or inconsistently wound meshes)
        const double diffuse = std::max(0.0, dot(n, light_));
        // Two tones with a soft terminator, as a painted study would have.
        const double tone = 0.60 + 0.32 * smoothstep(0.18, 0.38, diffuse) + 0.12 * diffuse;
        for (int k = 0; k < 3; ++k) out[k] = float(std::min(1.0, opt.fill[std::size_t(k)] * tone));
        return true;
    }

private:
    const ArtScene& s_;
    const std::vector<char>& on_line_;
    const ArtOptions& opt_;
    Vec3d d_, light_;
};

// The picture: each pixel the mean of its samples, with paper grain where it shows paper.
Image average_down(const ArtScene& s, const SampleShader& shade, int width, int height, const ArtOptions& opt) {
    const int ss = s.ss;
    Image img;
    img.width = width;
    img.height = height;
    img.channels = 4;
    img.pixels.assign(std::size_t(width) * height * 4, 1.0f);
    const float inv = 1.0f / float(ss * ss);
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            float acc[3] = {0, 0, 0};
            int covered = 0;
            for (int sy = 0; sy < ss; ++sy)
                for (int sx = 0; sx < ss; ++sx) {
                    float c[3];
                    covered += shade(x * ss + sx, y * ss + sy, c);
                    for (int k = 0; k < 3; ++k) acc[k] += c[k];
                }
            const double g =
                opt.grain > 0 ? opt.grain * (2 * hash01(std::uint64_t(x), std::uint64_t(y), opt.seed) - 1) : 0.0;
            const double on_paper = 1.0 - 0.7 * double(covered) * inv;
            float* out = &img.pixels[(std::size_t(y) * width + x) * 4];
            for (int k = 0; k < 3; ++k) out[k] = std::clamp(float(acc[k] * inv + g * on_paper), 0.0f, 1.0f);
        }
    });
    return img;
}

} // namespace

Image render_art(const Mesh& mesh_in, const Camera& cam, int width, int height, const ArtOptions& opt,
                 Progress progress) {
    if (width <= 0 || height <= 0)
        throw Error("cannot draw an image of size " + std::to_string(width) + "x" + std::to_string(height));
    // Samples per pixel, kept to about 12 M samples so large images stay within memory.
    int ss = std::max(1, opt.supersample);
    while (ss > 1 && double(width) * height * ss * ss > 12e6) --ss;
    const int W = width * ss, H = height * ss;
    const Camera hi = resized_camera(cam, ss);
    Mesh mesh = mesh_in;
    if (mesh.normals.size() != mesh.positions.size()) mesh.compute_normals();
    // Over the samples the mesh can cover, with a rim of two empty ones; the rest is paper.
    // A centred outline reaches half its width beyond the silhouette: the window holds it.
    const int rim = 2 + (opt.lines && opt.outline_centred ? int(std::ceil(0.5f * opt.outline_px * float(ss))) : 0);
    const DepthImage D = render_depth(mesh, hi, W, H, covered_window(mesh, hi, W, H, rim), progress);
    const int w = D.width, h = D.height;
    const std::size_t N = std::size_t(w) * h;
    ArtScene scene{mesh, cam, hi, D, W, H, ss, face_normals(mesh), std::vector<char>(N)};
    for (std::size_t i = 0; i < N; ++i) scene.empty[i] = D.face[i] == DepthImage::kNoFace;

    // Lines: silhouette outline inside the silhouette, and creases / inner contours.
    std::vector<char> crease = opt.lines ? crease_samples(scene, opt) : std::vector<char>(N, 0);
    if (opt.lines && opt.outline_centred) {
        // A centred outline is the line there: a crease or contour within it (a smooth
        // surface's contour generator, a rim on the edge) would ink it again further in, so
        // crease lines stop where their band meets the outline's inner edge.
        const float reach = 0.5f * (opt.outline_px + opt.crease_px) * float(ss);
        const std::vector<char> near_edge = within_chamfer(scene.empty, w, h, true, reach);
        for (std::size_t i = 0; i < N; ++i) crease[i] = crease[i] && !near_edge[i];
    }
    progress.check();
    // A sample is on a line within the outline's width of the outside or half a crease's width
    // of a crease. Over the window: its rim is empty (or the picture's edge, outside as there),
    // and nearer to any sample in it than an empty sample beyond it.
    std::vector<char> on_line;
    if (opt.lines) {
        if (opt.outline_centred) {
            // Within half the width of the edge on either side: near the outside and inside,
            // or near the inside and outside (each call also marks its own seeds).
            const float half = 0.5f * opt.outline_px * float(ss);
            on_line = within_chamfer(scene.empty, w, h, true, half);
            std::vector<char> covered(N);
            for (std::size_t i = 0; i < N; ++i) covered[i] = !scene.empty[i];
            const std::vector<char> near_inside = within_chamfer(covered, w, h, false, half);
            for (std::size_t i = 0; i < N; ++i) on_line[i] = on_line[i] && near_inside[i];
        } else {
            on_line = within_chamfer(scene.empty, w, h, true, opt.outline_px * float(ss));
        }
        const std::vector<char> near_crease = within_chamfer(crease, w, h, false, 0.5f * opt.crease_px * float(ss));
        for (std::size_t i = 0; i < N; ++i) on_line[i] |= near_crease[i];
    }
    progress.check();
    return average_down(scene, SampleShader(scene, on_line, opt), width, height, opt);
}

} // namespace cm
