// conceptmesh preview: a contact sheet of a mesh against its views (or against itself),
// through the eval.preview stage.
#include <algorithm>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/tool_common.h"
#include "io/limits.h"
#include "pipeline/run_stage.h"
#include "render/raster.h"
#include "render/shade.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::cli {

namespace {

struct PreviewOptions {
    std::string mesh, manifest, out, fit = "none", views = "front,right,top";
    AxisOptions axes;
    int panel = 320;
};

// Views of the mesh itself, framed as render-views frames them: art drawings as the
// images, the pixel-centre masks as the silhouettes.
Views self_views(const Mesh& mesh, const std::vector<ViewSpec>& specs, int size) {
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    Views views;
    for (const auto& s : specs) {
        View v;
        v.name = s.name;
        v.width = v.height = size;
        v.camera = framed_camera(s.dir, Vec3d(lo), Vec3d(hi), size, size);
        v.image = render_art(mesh, v.camera, size, size);
        const auto m = render_mask(mesh, v.camera, size, size);
        v.coverage = Coverage(std::vector<float>(m.begin(), m.end()), size, size);
        views.views.push_back(std::move(v));
    }
    return views;
}

int run_preview(const PreviewOptions& o, const GlobalOptions& g) {
    // About 310 bytes per pixel of one panel at the peak (all panels, their renders and the
    // sheet), measured at 2048 px panels.
    check_memory_estimate(std::uint64_t(310.0 * double(o.panel) * double(o.panel)),
                          "a preview of " + std::to_string(o.panel) + " px panels", "lower --panel");
    Mesh mesh = load_oriented(o.mesh, o.axes.parse());
    std::shared_ptr<const Views> views;
    if (o.manifest.empty()) {
        views = std::make_shared<Views>(self_views(mesh, parse_views(o.views), std::clamp(2 * o.panel, 128, 1024)));
    } else {
        views = load_views_through_registry(o.manifest, g);
        fit_mesh(mesh, *views, o.fit);
    }
    const std::string title = fs::path(o.mesh).filename().string() +
                              (o.manifest.empty() ? std::string() : " / " + fs::path(o.manifest).filename().string());
    const StageRun run = run_stage(Registry::global(), "eval.preview",
                                   text_params({{"path", o.out}, {"panel", std::to_string(o.panel)}, {"title", title}}),
                                   mesh_and_views(std::move(mesh), views));
    if (!g.quiet)
        std::cerr << "conceptmesh: wrote " << o.out << " (xor " << std::fixed << std::setprecision(3)
                  << json::parse(run.metrics_json.at("xor_pct")).get<double>() << "%, mean IoU " << std::setprecision(4)
                  << json::parse(run.metrics_json.at("mean_iou")).get<double>() << ")\n";
    return 0;
}

} // namespace

void add_preview_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd = app.add_subcommand(
        "preview", "Contact sheet: per view the input drawing, the mesh, and an overlay of the silhouettes");
    auto o = std::make_shared<PreviewOptions>();
    cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
    cmd->add_option("-o,--output", o->out, "Sheet image (.png)")->required();
    cmd->add_option("--views", o->manifest,
                    "Views manifest (YAML); without it the mesh is drawn from front, right and top against itself");
    add_fit_option(cmd, o->fit,
                   "bbox: map the mesh's bounding box onto the box the aligned views imply; pivot: move the mesh so "
                   "its box's bottom centre is at the origin, keeping its size");
    o->axes.add_to(cmd, "The mesh's own up axis", "The mesh's own front axis");
    cmd->add_option("--panel", o->panel, "Panel size in pixels")->capture_default_str()->check(CLI::Range(32, 4096));
    cmd->add_flag("-q,--quiet", g.quiet, "Only errors");
    set_action(cmd, action, [&g, o] { return run_preview(*o, g); });
}

} // namespace cm::cli
