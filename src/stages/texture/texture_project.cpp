// texture.project: the model in the colours of its drawings: per-vertex colours and a
// base-colour atlas (texture_bake.h), for the writers to put into .glb, .obj + .mtl + .png
// and .ply.
#include <memory>

#include <nlohmann/json.hpp>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "texture_bake.h"

namespace cm {
namespace {

class TextureProject : public Stage {
    TextureOptions opt_;
    double line_width_ = 4, line_contrast_ = 0.12, erode_px_ = 2, blend_px_ = 3;

public:
    StageSignature signature() const override {
        return {"texture.project",
                "Colour the mesh from its drawings: per-vertex colours and a texture atlas of charts per view "
                "direction, ink lines and the silhouette border left out, unseen parts from the nearest seen colour",
                {{"mesh", DataKind::Mesh, "the mesh to colour (after reduction: few, large charts)"},
                 {"views", DataKind::Views, "the drawings, their silhouettes and cameras"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        b.add(opt_.texture,
              ParamSpec::Bool("texture", true, "bake a texture atlas and UVs; false: vertex colours only"));
        b.add(opt_.texture_size,
              ParamSpec::Int("texture_size", 2048, 64, 16384, "texels", "width and height of the atlas image"));
        b.add(opt_.padding, ParamSpec::Int("padding", 4, 0, 64, "texels",
                                           "free texels around each chart, filled from its border (against bleeding "
                                           "in filtering and mipmaps)"));
        b.add(opt_.clean.strip_lines,
              ParamSpec::Bool("strip_lines", true,
                              "leave out ink strokes (outlines, hatching: thin, dark, high-contrast) and fill them "
                              "from the neighbouring fill colour"));
        b.add(line_width_,
              ParamSpec::Float("line_width", 4, 1, 64, "px", "the widest stroke taken for ink (strip_lines)"));
        b.add(line_contrast_, ParamSpec::Float("line_contrast", 0.12, 0.01, 1, "",
                                               "how much darker (luminance, 0-1) than the fill around it a stroke is"));
        b.add(erode_px_, ParamSpec::Float("erode", 2, 0, 64, "px",
                                          "silhouette border not sampled (the background bleeds in there)"));
        b.add(blend_px_, ParamSpec::Float("blend", 3, 0.5, 64, "px",
                                          "width over which a view's say fades out towards the eroded border and "
                                          "the mesh's occlusion edges in it, so views blend across seams (under ink "
                                          "a view has no say; beside it, full say)"));
        b.add(opt_.angle_power, ParamSpec::Float("angle_power", 2, 0, 16, "",
                                                 "a view's weight is cos(angle between normal and view)^angle_power"));
        b.add(opt_.conflict_de,
              ParamSpec::Float("conflict_de", 4, 0, 100, "delta E",
                               "views whose colours for a point differ by much more than this are not averaged: "
                               "the point takes the colour that costs the views least (a robust weighted median "
                               "in CIELAB); 0: the weighted mean of the views"));
        b.add(opt_.balance_rounds,
              ParamSpec::Int("balance_rounds", 16, 0, 100, "",
                             "evaluations of the views' colour errors (each view's mean delta E at its own pixels, "
                             "ink left out, of the colour the mesh gets there) while weighting the views: every "
                             "view's pixels count alike, and when a view is over balance_target the weights are "
                             "searched; 0: every view weighs 1"));
        b.add(opt_.balance_target,
              ParamSpec::Float("balance_target", 3, 0, 100, "delta E",
                               "the mean colour error a view is held to: views over it weigh more until they are "
                               "at it, or as far over it as each other; under it, the sum of the views' errors is "
                               "what is made small. 0: the worst view's error alone"));
        b.add(opt_.min_island_faces,
              ParamSpec::Int("min_island_faces", 8, 1, 1000000, "faces",
                             "chart islands with fewer faces join a neighbouring chart where its projection allows"));
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; nothing to colour");
        TextureOptions opt = opt_;
        opt.clean.line_width = float(line_width_);
        opt.clean.line_contrast = float(line_contrast_);
        opt.clean.erode_px = float(erode_px_);
        opt.clean.blend_px = float(blend_px_);
        TextureStats stats;
        auto out = std::make_shared<Mesh>(
            project_texture(*mesh, *views, opt, stats, [&](double f) { ctx.progress(f, "texturing"); }));
        ctx.metric("seen_vertices", stats.seen_vertices);
        if (opt.texture) {
            ctx.metric("charts", double(stats.charts));
            ctx.metric("texels_per_unit", stats.texels_per_unit);
            ctx.metric("atlas_fill", stats.atlas_fill);
        }
        nlohmann::json lines = nlohmann::json::object(); // view names escaped as JSON needs
        for (std::size_t i = 0; i < stats.line_pixels.size(); ++i) lines[stats.views[i]] = stats.line_pixels[i];
        if (opt.clean.strip_lines) ctx.metric_json("ink_pixels", lines.dump());
        nlohmann::json weight = nlohmann::json::object(), err = nlohmann::json::object(),
                       before = nlohmann::json::object();
        for (std::size_t i = 0; i < stats.views.size(); ++i) {
            weight[stats.views[i]] = stats.view_weight[i];
            err[stats.views[i]] = stats.view_error[i];
            before[stats.views[i]] = stats.view_error_unbalanced[i];
        }
        ctx.metric_json("view_delta_e", err.dump());
        if (opt.balance_rounds > 0) {
            ctx.metric_json("view_weight", weight.dump());
            ctx.metric_json("view_delta_e_unbalanced", before.dump());
        }
        if (stats.seen_vertices < 0.5)
            ctx.warn("the views see only " + std::to_string(int(stats.seen_vertices * 100)) +
                     " % of the vertices; the rest take the nearest seen colour");
        return std::shared_ptr<const Mesh>(out);
    }
};

} // namespace

Stage* make_texture_project() { return new TextureProject; }

} // namespace cm
