// SVG drawings, rasterised by librsvg (Debian's librsvg2, the renderer GNOME and ImageMagick
// use) onto a cairo image: a library of its own that io/image_io.cpp opens on the first SVG
// file, so the processes that never read one do not load librsvg, cairo and GLib.
#include <cairo.h>
#include <librsvg/rsvg.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "io/image_backend.h"

namespace {

using cm::RawImage;

struct HandleFree {
    void operator()(RsvgHandle* h) const { g_object_unref(h); }
};
struct SurfaceFree {
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct CairoFree {
    void operator()(cairo_t* c) const { cairo_destroy(c); }
};

std::string take_message(GError*& e, const char* otherwise) {
    std::string m = e && e->message ? e->message : otherwise;
    g_clear_error(&e);
    // One line: libxml ends its messages with a newline and may hold more.
    std::replace(m.begin(), m.end(), '\n', ' ');
    while (!m.empty() && m.back() == ' ') m.pop_back();
    return m;
}

// The drawing's own size in its units: width and height when it gives them (in px, mm, ...),
// else its viewBox.
bool own_size(RsvgHandle* h, double& w, double& ht, std::string& why) {
    if (rsvg_handle_get_intrinsic_size_in_pixels(h, &w, &ht) && w > 0 && ht > 0) return true;
    gboolean has_w = FALSE, has_h = FALSE, has_box = FALSE;
    RsvgLength lw{}, lh{};
    RsvgRectangle box{};
    rsvg_handle_get_intrinsic_dimensions(h, &has_w, &lw, &has_h, &lh, &has_box, &box);
    if (has_box && box.width > 0 && box.height > 0) {
        w = box.width, ht = box.height;
        return true;
    }
    why = "the SVG gives no size (no width and height in absolute units, no viewBox)";
    return false;
}

bool rasterise(const std::string& file, int longest, std::uint64_t max_pixels, RawImage& out, std::string& why) {
    GError* e = nullptr;
    std::unique_ptr<RsvgHandle, HandleFree> h(rsvg_handle_new_from_file(file.c_str(), &e));
    if (!h) return why = "not a readable SVG: " + take_message(e, "librsvg could not parse it"), false;
    double w = 0, ht = 0;
    if (!own_size(h.get(), w, ht, why)) return false;
    const double scale = double(longest) / std::max(w, ht);
    const int pw = std::max(1, int(std::lround(w * scale))), ph = std::max(1, int(std::lround(ht * scale)));
    if (max_pixels && std::uint64_t(pw) * std::uint64_t(ph) > max_pixels)
        return why = cm::over_pixel_limit(pw, ph, max_pixels), false;
    std::unique_ptr<cairo_surface_t, SurfaceFree> surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, pw, ph));
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
        return why = "cannot make a " + std::to_string(pw) + " x " + std::to_string(ph) + " image to draw it on", false;
    std::unique_ptr<cairo_t, CairoFree> cr(cairo_create(surface.get()));
    // On white paper, as drawings are scanned: the drawing's own background, if any, over it.
    cairo_set_source_rgb(cr.get(), 1, 1, 1);
    cairo_paint(cr.get());
    const RsvgRectangle viewport{0, 0, double(pw), double(ph)};
    if (!rsvg_handle_render_document(h.get(), cr.get(), &viewport, &e))
        return why = "librsvg could not draw it: " + take_message(e, "no reason given"), false;
    cairo_surface_flush(surface.get());
    const unsigned char* px = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    out.width = pw, out.height = ph, out.channels = 3, out.bits = 8, out.file_bits = 8, out.alpha = -1;
    out.data.resize(std::size_t(pw) * std::size_t(ph) * 3);
    for (int y = 0; y < ph; ++y) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(px + std::size_t(y) * std::size_t(stride));
        unsigned char* d = out.data.data() + std::size_t(y) * std::size_t(pw) * 3;
        for (int x = 0; x < pw; ++x) { // xRGB in a native 32-bit word
            d[3 * x] = (row[x] >> 16) & 0xFF;
            d[3 * x + 1] = (row[x] >> 8) & 0xFF;
            d[3 * x + 2] = row[x] & 0xFF;
        }
    }
    return true;
}

const cm::VectorBackend kBackend{cm::kVectorBackendAbi, &rasterise};

} // namespace

extern "C" const cm::VectorBackend* conceptmesh_vector_backend() { return &kBackend; }
