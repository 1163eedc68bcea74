// real_drawings_pictures OUT_DIR [PHOTO]: the before/after pictures of docs/views.md
// ("Drawings as they are handed over"): for a broken outline, a cloth reaching the frame, a
// ground shadow and a photograph with shadows on the object, the input beside the
// silhouette without and with the handling (PNG, 3 panels of 200 x 200 px each). With
// PHOTO (a photograph, e.g. one of bench/views/dino_cloth's), also views-photo-real.png: the
// photograph segmented as a drawing and as a photograph, at half its size.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "io/image_io.h"
#include "silhouette.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

constexpr int kSize = 200;
using Colour = std::array<float, 3>;

double sdf(double x, double y) { // a body (box) under a head (disc), positive inside
    const double qx = std::abs(x - 100) - 45, qy = std::abs(y - 135) - 35;
    const double box = qx > 0 || qy > 0 ? -std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) : -std::max(qx, qy);
    return std::max(box, 37.0 - std::hypot(x - 100, y - 70));
}

Image render(const std::function<Colour(double, double)>& f) {
    Image img;
    img.width = img.height = kSize;
    img.channels = 4;
    img.pixels.assign(std::size_t(kSize) * kSize * 4, 1.0f);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            Colour sum{};
            for (int s = 0; s < 16; ++s) {
                const Colour c = f(x + (s % 4 + 0.5) / 4, y + (s / 4 + 0.5) / 4);
                for (int k = 0; k < 3; ++k) sum[std::size_t(k)] += c[std::size_t(k)] / 16;
            }
            for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * kSize + x) * 4 + k] = sum[std::size_t(k)];
        }
    return img;
}

// The input, then the silhouette under `before` and under `after`, side by side; each panel
// `shrink` times smaller than the input (the mean of shrink x shrink pixels).
void sheet(const Image& in, const SilhouetteOptions& before, const SilhouetteOptions& after, const fs::path& file,
           int shrink = 1) {
    const ImageInfo info;
    const std::vector<float> a = extract_silhouette(in, info, before).coverage.full();
    const std::vector<float> b = extract_silhouette(in, info, after).coverage.full();
    const int w = in.width / shrink, h = in.height / shrink;
    Image out;
    out.width = 3 * w + 8;
    out.height = h;
    out.channels = 3;
    out.pixels.assign(std::size_t(out.width) * h * 3, 0.55f);
    for (int y = 0; y < h; ++y) // the panels start black: their pixels are sums
        for (int p = 0; p < 3; ++p)
            for (int x = 0; x < w; ++x)
                for (std::size_t k = 0; k < 3; ++k)
                    out.pixels[(std::size_t(y) * out.width + p * (w + 4) + x) * 3 + k] = 0;
    const float share = 1.0f / float(shrink * shrink);
    for (int y = 0; y < h * shrink; ++y)
        for (int x = 0; x < w * shrink; ++x) {
            const std::size_t i = std::size_t(y) * in.width + x;
            const std::size_t o = std::size_t(y / shrink) * out.width + std::size_t(x / shrink);
            for (std::size_t k = 0; k < 3; ++k) {
                out.pixels[o * 3 + k] += share * in.pixels[i * 4 + k];
                out.pixels[(o + std::size_t(w) + 4) * 3 + k] += share * a[i];
                out.pixels[(o + 2 * std::size_t(w) + 8) * 3 + k] += share * b[i];
            }
        }
    write_image(out, file);
    std::printf("wrote %s\n", file.string().c_str());
}

// A plaster figure lit from the upper left on dark velvet, a dark stand behind it and a
// cloth reaching the frame; a crevice in shadow reaches its outline, a pocket is enclosed.
Image plaster_photo() {
    std::mt19937 rng(6);
    std::normal_distribution<float> noise(0, 0.006f);
    Image img = render([](double x, double y) -> Colour {
        if (sdf(x, y) >= 0) {
            const bool dark = (std::abs(y - 125 - 0.3 * (x - 100)) < 3.5 && x > 75) || std::hypot(x - 80, y - 150) < 7;
            const double light = dark ? 0.13 : 0.55 + 0.45 * std::clamp(1.2 - (x + y) / 250, 0.0, 1.0);
            return {float(0.82 * light), float(0.79 * light), float(0.72 * light)};
        }
        if (y > 182 + 3 * std::sin(x / 20)) {
            const float weave = 0.04f * float(std::sin(x * 1.8) * std::sin(y * 1.8));
            return {0.33f + weave, 0.26f + weave, 0.2f + weave};
        }
        if (x > 30 && x < 62) return {0.095f, 0.063f, 0.047f};
        return {0.035f, 0.022f, 0.016f};
    });
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        if (i % 4 != 3) img.pixels[i] = std::round(std::clamp(img.pixels[i] + noise(rng), 0.0f, 1.0f) * 255) / 255;
    return img;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: real_drawings_pictures OUT_DIR [PHOTO]\n");
        return 2;
    }
    const fs::path dir = argv[1];
    fs::create_directories(dir);
    // A sketchy outline: 1.5 px stroke just inside the outline, broken every ~40 px.
    const Image sketch = render([](double x, double y) -> Colour {
        const double f = sdf(x, y);
        const double along = std::atan2(y - 110, x - 100) * 60;
        const bool gap = std::fmod(along + 1000, 37.0) < 3.0;
        return f >= 0 && f <= 1.5 && !gap ? Colour{0.12f, 0.12f, 0.14f} : Colour{0.97f, 0.96f, 0.93f};
    });
    SilhouetteOptions off, on;
    off.close_gaps = 0;
    sheet(sketch, off, on, dir / "views-close-gaps.png");
    // A white object on a light backdrop, standing on a dark cloth that reaches the frame.
    std::mt19937 rng(2);
    std::normal_distribution<float> grain(0, 0.02f);
    const Image photo = render([&](double x, double y) -> Colour {
        if (sdf(x, y) >= 0) return {0.94f, 0.94f, 0.92f};
        if (y > 150 + 4 * std::sin(x / 20)) {
            const float g = 0.04f * float(std::sin(x * 0.9) * std::sin(y * 0.9)) + grain(rng);
            return {0.33f + g, 0.26f + g, 0.2f + g};
        }
        return {0.72f, 0.75f, 0.8f};
    });
    SilhouetteOptions given, automatic;
    given.background = "184,191,204";
    sheet(photo, given, automatic, dir / "views-border-colours.png");
    // A soft grey shadow under a coloured object.
    const Image shadow = render([](double x, double y) -> Colour {
        if (sdf(x, y) >= 0) return {0.3f, 0.42f, 0.7f};
        const double e = std::hypot((x - 103) / 65, (y - 171) / 8);
        const float s = e < 1 ? float(1 - 0.3 * (1 - e * e)) : 1.0f;
        return {0.96f * s, 0.95f * s, 0.92f * s};
    });
    SilhouetteOptions keep, remove;
    keep.shadow = "keep";
    sheet(shadow, keep, remove, dir / "views-shadow.png");
    // Photographs: segmented as a drawing, then as a photograph.
    SilhouetteOptions as_drawing, as_photo;
    as_drawing.photo = "off";
    as_photo.photo = "on";
    sheet(plaster_photo(), as_drawing, as_photo, dir / "views-photo.png");
    if (argc == 3) {
        as_drawing.threshold = as_photo.threshold = 0.19; // the dinoSparseRing authors' value
        sheet(read_image(argv[2]), as_drawing, as_photo, dir / "views-photo-real.png", 2);
    }
    return 0;
}
