// texture.project: the model in the colours of its drawings: per-vertex colours and a
// base-colour atlas (texture_bake.h), for the writers to put into .glb, .obj + .mtl + .png
// and .ply.
#include <memory>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "texture_bake.h"

namespace cm {
namespace {

class TextureProject : public Stage {
    TextureOptions opt_;

public:
    StageSignature signature() const override {
        return {"texture.project",
                "Colour the mesh from its drawings: per-vertex colours and a texture atlas of charts per view "
                "direction, ink lines and the silhouette border left out, unseen parts from the nearest seen colour",
                {{"mesh", DataKind::Mesh, "the mesh to colour (after reduction: few, large charts)"},
                 {"views", DataKind::Views, "the drawings, their silhouettes and cameras"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override { opt_.declare(b); }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; nothing to colour");
        auto [out, stats] = project_texture(*mesh, *views, opt_, ctx.progress("texturing"));
        stats.report(ctx);
        return std::make_shared<const Mesh>(std::move(out));
    }
};

} // namespace

Stage* make_texture_project() { return new TextureProject; }

} // namespace cm
