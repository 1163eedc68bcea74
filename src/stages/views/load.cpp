#include "load.h"

#include <algorithm>
#include <atomic>

#include <tbb/parallel_for.h>

#include "align.h"
#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "sheet.h"
#include "silhouette.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// A view whose manifest entry gives a mask: white (or alpha, where the mask has alpha
// that separates something) is the object, grey its fractional coverage. The mask stands
// for the drawing's segmentation; it must have the drawing's size.
SilhouetteResult silhouette_from_mask(const ManifestView& mv, const Image& image) {
    ImageInfo info;
    const Image m = read_image(mv.mask, &info);
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

} // namespace

Views load_views(const fs::path& manifest, const LoadViewsOptions& opt, LoadViewsReport& report,
                 const std::function<void(double)>& progress) {
    const Manifest man = read_manifest(manifest);
    Views views;
    views.manifest = man.file;
    views.views.resize(man.views.size());
    std::size_t perspective = 0;
    for (const auto& mv : man.views) perspective += mv.matrix.has_value();
    if (perspective != 0 && perspective != man.views.size())
        throw Error(man.file.string() + ": mixes calibrated (matrix) and drawn views; use one kind per manifest");
    views.calibrated = perspective != 0;
    if (views.calibrated && (man.height || man.width || man.depth))
        throw Error(man.file.string() +
                    ": a real size (height, width, depth) applies to drawn views; calibrated views keep "
                    "the calibration's units");

    SheetViews sheets = split_sheets(man); // the panels of turnaround sheets, each a view's drawing
    report.notes.insert(report.notes.end(), sheets.notes.begin(), sheets.notes.end());
    std::vector<std::string> errors(man.views.size()), notes(man.views.size());
    // A stop is looked for per view and per step of a view (reading, extracting), from the
    // workers: one view's image is the chunk.
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
            ImageInfo info = sheets.infos[i];
            v.image = sheets.on_sheet(i) ? std::move(sheets.images[i]) : read_image(mv.image, &info, true);
            v.width = v.image.width;
            v.height = v.image.height;
            step();
            SilhouetteOptions so;
            so.background = mv.background;
            so.threshold = mv.threshold.value_or(-1.0);
            so.keep = mv.keep != "auto" ? mv.keep : opt.keep;
            so.holes = mv.holes;
            so.close_gaps = mv.close_gaps.value_or(-1.0);
            so.shadow = mv.shadow;
            // A calibrated camera is a photograph's (drawings are not calibrated).
            so.photo = mv.photo != "auto" ? mv.photo : mv.matrix ? "on" : "auto";
            SilhouetteResult s =
                mv.mask.empty() ? extract_silhouette(v.image, info, so) : silhouette_from_mask(mv, v.image);
            v.coverage = std::move(s.coverage);
            std::string note;
            if (s.components_dropped)
                note += "dropped " + std::to_string(s.components_dropped) +
                        " separate mark(s) away from the object (keep: all keeps them)";
            if (s.photo) {
                if (!note.empty()) note += "; ";
                note += "segmented as a photograph: " + std::to_string(s.grown) +
                        " px grown from the seeds beyond the threshold, " + std::to_string(s.regions_filled) +
                        " enclosed region(s) filled (photo: off segments it as a drawing)";
            } else if (s.regions_filled && s.holes_kept == 0 && s.regions_filled > 0 && so.holes == "auto") {
                if (!note.empty()) note += "; ";
                note += "filled " + std::to_string(s.regions_filled) +
                        " blank region(s) enclosed by the drawing (holes: keep keeps them open)";
            }
            if (!note.empty()) notes[i] = "view \"" + v.name + "\": " + note;
            if (mv.matrix) v.camera = Camera::perspective(*mv.matrix);
            else if (mv.view) v.camera = *Camera::named(*mv.view);
            else v.camera = Camera::from_azimuth_elevation(*mv.azimuth, *mv.elevation);
            if (mv.scale) {
                v.camera.scale = *mv.scale;
                v.camera.cx = (*mv.origin)[0];
                v.camera.cy = (*mv.origin)[1];
            }
        } catch (const Cancelled&) {
            throw;
        } catch (const std::exception& e) {
            errors[i] = "view \"" + mv.key + "\": " + e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    for (const auto& n : notes)
        if (!n.empty()) report.notes.push_back(n);
    if (progress) progress(0.8);

    for (const auto& v : views.views) {
        if (v.coverage.inside_box().empty())
            throw Error("view \"" + v.name + "\" (" + v.source.string() +
                        ") has an empty silhouette: no object was found in it");
    }
    if (views.calibrated) {
        if (man.bounds) {
            views.has_bounds = true;
            views.bounds_min = {(*man.bounds)[0], (*man.bounds)[1], (*man.bounds)[2]};
            views.bounds_max = {(*man.bounds)[3], (*man.bounds)[4], (*man.bounds)[5]};
        }
    } else {
        AlignOptions ao;
        ao.height = man.height;
        ao.width = man.width;
        ao.depth = man.depth;
        ao.tolerance = opt.align_tolerance;
        for (const auto& mv : man.views) ao.fixed.push_back(mv.scale.has_value());
        ao.bounds = man.bounds;
        align_views(views, ao, report.warnings);
    }
    return views;
}

Image silhouette_image(const View& v) {
    Image img;
    img.width = v.width;
    img.height = v.height;
    img.channels = 1;
    img.pixels = v.coverage.full();
    return img;
}

} // namespace cm
