// conceptmesh compare: silhouette error of a mesh against a views manifest, through
// the eval.silhouette_error stage.
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/tool_common.h"
#include "metrics/colour_error.h"
#include "pipeline/run_stage.h"
#include "render/textured.h"

using nlohmann::json;

namespace cm::cli {

namespace {

struct CompareOptions {
    std::string mesh, manifest, fit = "none";
    AxisOptions axes;
    bool json = false;
};

// One row of the table: a view of the report.
struct CompareRow {
    std::string view;
    double input_px = 0, render_px = 0, xor_px = 0, xor_pct = 0, iou = 0;
};

std::vector<CompareRow> compare_rows(const json& report) {
    std::vector<CompareRow> rows;
    for (const auto& v : report["views"])
        rows.push_back({v["view"], v["input_px"], v["render_px"], v["xor_px"], v["xor_pct"], v["iou"]});
    return rows;
}

void print_compare_table(std::ostream& os, const json& report) {
    os << std::left << std::setw(14) << "view" << std::right << std::setw(12) << "input px" << std::setw(12)
       << "mesh px" << std::setw(10) << "xor px" << std::setw(10) << "xor %" << std::setw(9) << "IoU"
       << "\n";
    for (const auto& v : compare_rows(report))
        os << std::left << std::setw(14) << v.view << std::right << std::fixed << std::setprecision(0) << std::setw(12)
           << v.input_px << std::setw(12) << v.render_px << std::setw(10) << v.xor_px << std::setprecision(3)
           << std::setw(10) << v.xor_pct << std::setprecision(4) << std::setw(9) << v.iou << "\n";
    os << std::left << std::setw(14) << "all" << std::right << std::fixed << std::setw(44) << std::setprecision(3)
       << report["xor_pct"].get<double>() << std::setprecision(4) << std::setw(9) << report["mean_iou"].get<double>()
       << "\n"
       << "xor % = 100 |input xor mesh| / |input| (all: summed over views); IoU per view, all: mean\n";
}

json compare_json(const CompareOptions& o, const json& report) {
    json j;
    j["xor_pct"] = report["xor_pct"];
    j["mean_iou"] = report["mean_iou"];
    j["fit"] = o.fit;
    j["mesh"] = o.mesh;
    j["views_manifest"] = o.manifest;
    j["views"] = report["views"];
    return j;
}

int run_compare(const CompareOptions& o, const GlobalOptions& g) {
    Mesh mesh = load_oriented(o.mesh, o.axes.parse());
    const auto views = load_views_through_registry(o.manifest, g);
    fit_mesh(mesh, *views, o.fit);
    // A mesh with colour (texture or vertex colours) is also compared with the drawings' colours.
    json colour = json::array();
    if (has_colour(mesh))
        for (const auto& e : colour_error(mesh, *views, 3.0))
            colour.push_back({{"view", e.view},
                              {"pixels", e.pixels},
                              {"mean_delta_e", e.mean_de},
                              {"over10_pct", e.over10_pct},
                              {"no_ink_pixels", e.no_ink_pixels},
                              {"no_ink_mean_delta_e", e.no_ink_mean_de},
                              {"no_ink_over10_pct", e.no_ink_over10_pct}});
    const StageRun run =
        run_stage(Registry::global(), "eval.silhouette_error", {}, mesh_and_views(std::move(mesh), views));
    const json report = json::parse(std::get<std::shared_ptr<const Report>>(run.output)->json);
    if (o.json) {
        json j = compare_json(o, report);
        if (!colour.empty()) j["colour"] = colour;
        std::cout << j.dump(2) << "\n";
    } else {
        print_compare_table(std::cout, report);
        if (!colour.empty()) {
            std::cout << "\n"
                      << std::left << std::setw(14) << "view" << std::right << std::setw(12) << "pixels"
                      << std::setw(12) << "mean dE" << std::setw(12) << "dE>10 %" << std::setw(12) << "no ink px"
                      << std::setw(12) << "mean dE" << std::setw(12) << "dE>10 %"
                      << "\n";
            for (const auto& c : colour)
                std::cout << std::left << std::setw(14) << c["view"].get<std::string>() << std::right << std::fixed
                          << std::setprecision(0) << std::setw(12) << c["pixels"].get<double>() << std::setprecision(2)
                          << std::setw(12) << c["mean_delta_e"].get<double>() << std::setw(12)
                          << c["over10_pct"].get<double>() << std::setprecision(0) << std::setw(12)
                          << c["no_ink_pixels"].get<double>() << std::setprecision(2) << std::setw(12)
                          << c["no_ink_mean_delta_e"].get<double>() << std::setw(12)
                          << c["no_ink_over10_pct"].get<double>() << "\n";
            std::cout << "dE = CIE76 colour difference of the mesh's colour (unlit) and the drawing, inside the "
                         "silhouette eroded by 3 px; no ink: without the drawing's ink strokes (thin, dark, high "
                         "contrast, found as texture.project finds them), which have no fill colour\n";
        }
    }
    return 0;
}

} // namespace

void add_compare_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd =
        app.add_subcommand("compare", "Silhouette error of a mesh against the views of a manifest (xor_pct and IoU)");
    auto o = std::make_shared<CompareOptions>();
    cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off)")->required();
    cmd->add_option("views", o->manifest, "Views manifest (YAML), loaded as views.load loads it")->required();
    cmd->add_flag("--json", o->json, "Print a JSON object (top-level xor_pct, mean_iou, views)");
    add_fit_option(cmd, o->fit,
                   "bbox: first map the mesh's bounding box onto the box the aligned views imply; pivot: move the "
                   "mesh so its box's bottom centre is at the origin, keeping its size");
    o->axes.add_to(cmd, "The mesh's own up axis", "The mesh's own front axis");
    cmd->add_flag("-q,--quiet", g.quiet, "No warnings from loading the views");
    cmd->add_flag("-v,--verbose", g.verbose, "Also say what loading the views dropped or filled");
    set_action(cmd, action, [&g, o] { return run_compare(*o, g); });
}

} // namespace cm::cli
