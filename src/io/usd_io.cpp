#include "io/usd_io.h"

#include <algorithm>
#include <string_view>
#include <utility>
#include <vector>

#include "core/data.h"
#include "core/views.h"
#include "io/image_io.h"
#include "io/number_text.h"
#include "io/progress_stream.h"
#include "io/zip_store.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// Every this many elements the layer's text reports its progress (and may be stopped).
constexpr std::size_t kProgressEvery = 1 << 16;

struct LayerOptions {
    std::string prim;    ///< the asset's prim name (an identifier)
    bool normals = true; ///< author the mesh's normals when it has them
    std::string texture; ///< the texture's path relative to the layer; empty: no material
};

// `path` as a USD asset path: @path@, or @@@path@@@ when it holds an @.
std::string asset_path(const std::string& path) {
    return path.find('@') == std::string::npos ? "@" + path + "@" : "@@@" + path + "@@@";
}

// The layer's text, built in the order a reader meets it: the layer's metadata, the asset's
// Xform, its Mesh, its Material. Arrays go on one line each, as USD writes them.
class LayerText {
public:
    LayerText(const Mesh& mesh, const LayerOptions& opt, Progress progress)
        : mesh_(mesh), opt_(opt), progress_(std::move(progress)) {
        const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
        total_ = double(nv * 3 + nf * 5) + 1;
        o_.reserve(nv * 80 + nf * 80 + 4096);
        metadata();
        o_ += "def Xform \"" + opt_.prim + "\" (\n    kind = \"component\"\n)\n{\n";
        geometry();
        if (!opt_.texture.empty()) material();
        o_ += "}\n";
    }
    std::string take() { return std::move(o_); }

private:
    const Mesh& mesh_;
    const LayerOptions& opt_;
    Progress progress_;
    std::string o_;
    double total_ = 1;
    std::size_t done_ = 0;

    void tick() {
        if (progress_ && ++done_ % kProgressEvery == 0) progress_(double(done_) / total_);
    }
    std::string material_path() const { return "/" + opt_.prim + "/mtl/" + opt_.prim; }

    void metadata() {
        o_ +=
            "#usda 1.0\n(\n    customLayerData = {\n        string creator = \"conceptmesh " CONCEPTMESH_VERSION_STRING
            "\"\n    }\n    defaultPrim = \"" +
            opt_.prim + "\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\n";
    }

    // `decl = [(a, b), ...]`: `count` tuples of `n` floats (plain numbers when n is 1), item
    // i's at `at(i)`; with an interpolation, as a primvar's metadata.
    template <typename At>
    void tuples(const std::string& decl, std::size_t count, int n, At at, const char* interpolation = nullptr) {
        o_ += "        " + decl + " = [";
        for (std::size_t i = 0; i < count; ++i) {
            tick();
            const float* x = at(i);
            if (i) o_ += ", ";
            if (n > 1) o_ += '(';
            for (int k = 0; k < n; ++k) {
                if (k) o_ += ", ";
                append_float(o_, x[k]);
            }
            if (n > 1) o_ += ')';
        }
        o_ += ']';
        if (interpolation) o_ += std::string(" (\n            interpolation = \"") + interpolation + "\"\n        )";
        o_ += '\n';
    }

    void geometry() {
        const Mesh& m = mesh_;
        const std::size_t nv = m.positions.size(), nf = m.triangles.size();
        o_ += "    def Mesh \"mesh\"";
        if (!opt_.texture.empty()) o_ += " (\n        prepend apiSchemas = [\"MaterialBindingAPI\"]\n    )";
        o_ += "\n    {\n";
        Vec3f lo, hi;
        m.bounds(lo, hi);
        const Vec3f box[2] = {lo, hi};
        tuples("float3[] extent", 2, 3, [&](std::size_t i) { return &box[i].x; });
        o_ += "        int[] faceVertexCounts = [";
        for (std::size_t f = 0; f < nf; ++f) o_ += f ? ", 3" : "3";
        o_ += "]\n        int[] faceVertexIndices = [";
        for (std::size_t f = 0; f < nf; ++f) {
            tick();
            for (int k = 0; k < 3; ++k) {
                if (f || k) o_ += ", ";
                append_index(o_, m.triangles[f][std::size_t(k)]);
            }
        }
        o_ += "]\n";
        if (!opt_.texture.empty()) o_ += "        rel material:binding = <" + material_path() + ">\n";
        if (opt_.normals && m.normals.size() == nv)
            tuples(
                "normal3f[] normals", nv, 3, [&](std::size_t i) { return &m.normals[i].x; }, "vertex");
        o_ += "        uniform token orientation = \"rightHanded\"\n";
        tuples("point3f[] points", nv, 3, [&](std::size_t i) { return &m.positions[i].x; });
        if (m.colors.size() == nv) {
            tuples(
                "color3f[] primvars:displayColor", nv, 3, [&](std::size_t i) { return m.colors[i].data(); }, "vertex");
            const bool opaque = std::all_of(m.colors.begin(), m.colors.end(), [](const auto& c) { return c[3] == 1; });
            if (!opaque)
                tuples(
                    "float[] primvars:displayOpacity", nv, 1, [&](std::size_t i) { return &m.colors[i][3]; }, "vertex");
        }
        if (m.corner_uvs.size() == 3 * nf)
            tuples(
                "texCoord2f[] primvars:st", 3 * nf, 2, [&](std::size_t i) { return m.corner_uvs[i].data(); },
                "faceVarying");
        else if (m.uvs.size() == nv)
            tuples(
                "texCoord2f[] primvars:st", nv, 2, [&](std::size_t i) { return m.uvs[i].data(); }, "vertex");
        o_ += "        uniform token subdivisionScheme = \"none\"\n    }\n";
    }

    // A matte UsdPreviewSurface whose diffuse colour is the texture, addressed by `st`.
    void material() {
        const std::string at = material_path();
        o_ += "\n    def Scope \"mtl\"\n    {\n        def Material \"" + opt_.prim +
              "\"\n        {\n"
              "            token outputs:surface.connect = <" +
              at +
              "/surface.outputs:surface>\n\n"
              "            def Shader \"surface\"\n            {\n"
              "                uniform token info:id = \"UsdPreviewSurface\"\n"
              "                color3f inputs:diffuseColor.connect = <" +
              at +
              "/texture.outputs:rgb>\n"
              "                float inputs:metallic = 0\n"
              "                float inputs:roughness = 1\n"
              "                token outputs:surface\n            }\n\n"
              "            def Shader \"texture\"\n            {\n"
              "                uniform token info:id = \"UsdUVTexture\"\n"
              "                asset inputs:file = " +
              asset_path("./" + opt_.texture) +
              "\n"
              "                token inputs:sourceColorSpace = \"sRGB\"\n"
              "                float2 inputs:st.connect = <" +
              at +
              "/uv.outputs:result>\n"
              "                token inputs:wrapS = \"clamp\"\n"
              "                token inputs:wrapT = \"clamp\"\n"
              "                float3 outputs:rgb\n            }\n\n"
              "            def Shader \"uv\"\n            {\n"
              "                uniform token info:id = \"UsdPrimvarReader_float2\"\n"
              "                string inputs:varname = \"st\"\n"
              "                float2 outputs:result\n            }\n        }\n    }\n";
    }
};

} // namespace

bool is_usd_file(const fs::path& file) {
    const std::string ext = lower_extension(file);
    return ext == ".usda" || ext == ".usdz";
}

std::string usd_identifier(const std::string& name) {
    std::string id;
    if (name.empty() || (name[0] >= '0' && name[0] <= '9')) id += '_';
    for (unsigned char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
        id += ok ? char(c) : '_';
    }
    return id;
}

void write_usd(const Mesh& mesh, const fs::path& file, const MeshWriteOptions& wo, Progress progress) {
    const std::string name = wo.name.empty() ? file.stem().string() : wo.name;
    const bool package = lower_extension(file) == ".usdz";
    const bool textured = has_texture_map(mesh);
    const MeshSideFiles side = mesh_side_files(file, mesh);
    LayerOptions opt;
    opt.prim = usd_identifier(name);
    opt.normals = wo.normals;
    if (textured)
        opt.texture = package                   ? name + "_basecolor.png"
                      : wo.texture_name.empty() ? side.texture.filename().string()
                                                : wo.texture_name;
    // Building the text takes most of the time; the files then go out in chunks.
    const std::string layer = LayerText(mesh, opt, progress.part(0, 0.6)).take();
    std::vector<unsigned char> png;
    if (textured) png = encode_png(*mesh.texture, 3);
    const std::string_view png_bytes(reinterpret_cast<const char*>(png.data()), png.size());
    if (package) {
        std::vector<ZipEntry> entries = {{name + ".usda", layer}};
        if (textured) entries.push_back({opt.texture, png_bytes});
        return write_zip_store(file, entries, progress.part(0.6, 1.0));
    }
    write_file_bytes(file, layer, progress.part(0.6, textured ? 0.8 : 1.0));
    if (textured)
        write_file_bytes(wo.texture_file.empty() ? side.texture : wo.texture_file, png_bytes, progress.part(0.8, 1.0));
}

} // namespace cm
