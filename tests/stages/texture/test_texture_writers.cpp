// The textured mesh in every format, opened by the readers a studio uses: tinygltf (and
// the Khronos glTF validator when node is present), OpenMesh and OpenImageIO; and the PNG
// files themselves (io/png_codec, written in parallel pieces), opened by OpenImageIO.
// OpenMesh's colour property trips GCC 12's -Wmaybe-uninitialized inside std::vector (library code).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>

#include <fstream>
#include <nlohmann/json.hpp>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <tbb/global_control.h>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

// tinygltf as the reader, compiled into this test as the writer does into the io library.
#define TINYGLTF_IMPLEMENTATION
#include "io/tinygltf_config.h"

#include "core/camera.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "io/mesh_io.h"
#include "io/png_codec.h"
#include "render/colour.h"
#include "support/stage_harness.h"
#include "support/test_support.h"
#include "texture_views.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

std::vector<View> box_drawings() {
    const Vec3d lo(-1, -1, -1), hi(1, 1, 1);
    std::vector<View> vs;
    const test::Rgb colours[3] = {{0.9f, 0.2f, 0.1f}, {0.1f, 0.3f, 0.9f}, {0.2f, 0.8f, 0.3f}};
    int k = 0;
    for (const char* name : {"front", "right", "top"}) {
        const test::Rgb c = colours[k++];
        vs.push_back(test::painted_view(name, 96, 36, test::box_outline(lo, hi, Camera::named(name)->d),
                                        [c](const Vec3d&) { return c; }));
    }
    return vs;
}

std::shared_ptr<const Mesh> textured_box() {
    const Vec3d lo(-1, -1, -1), hi(1, 1, 1);
    const std::vector<View> vs = box_drawings();
    test::StageHarness h("texture.project");
    h.params("{texture_size: 128, padding: 2}")
        .input("mesh", test::make_grid_box(-1, 1, 3))
        .input("views", test::make_views(vs, lo, hi));
    return h.run<Mesh>();
}

void write(const std::shared_ptr<const Mesh>& m, const fs::path& path, const std::string& extra = {}) {
    test::StageHarness h("mesh.write");
    h.param("path", path).input("mesh", m);
    if (!extra.empty()) h.params(extra);
    h.run<FileOutput>();
}

bool keep_png(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
              int size, void*) {
    image->image.assign(bytes, bytes + size); // the encoded file, checked below with OpenImageIO
    return size > 8;
}

} // namespace

TEST(TexturedWriters, GlbHasTheEmbeddedPngUvsAndAMatteMaterialNamedAfterTheFile) {
    test::TempDir dir("tex_glb");
    const auto m = textured_box();
    write(m, dir / "crate.glb");
    tinygltf::Model model;
    tinygltf::TinyGLTF io;
    io.SetImageLoader(&keep_png, nullptr);
    std::string err, warn;
    ASSERT_TRUE(io.LoadBinaryFromFile(&model, &err, &warn, (dir / "crate.glb").string())) << err;
    ASSERT_EQ(model.nodes.size(), 1u);
    EXPECT_EQ(model.nodes[0].name, "crate"); // not the temporary file's name
    ASSERT_EQ(model.meshes.size(), 1u);
    EXPECT_EQ(model.meshes[0].name, "crate");
    const auto& prim = model.meshes[0].primitives.at(0);
    EXPECT_TRUE(prim.attributes.count("TEXCOORD_0"));
    EXPECT_TRUE(prim.attributes.count("NORMAL"));
    EXPECT_TRUE(prim.attributes.count("_COLOR_0")); // vertex colours that do not tint the texture
    EXPECT_FALSE(prim.attributes.count("COLOR_0"));
    ASSERT_GE(prim.material, 0);
    const auto& mat = model.materials.at(std::size_t(prim.material));
    EXPECT_EQ(mat.pbrMetallicRoughness.metallicFactor, 0.0);
    EXPECT_EQ(mat.pbrMetallicRoughness.roughnessFactor, 1.0);
    const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
    ASSERT_GE(tex, 0);
    const auto& img = model.images.at(std::size_t(model.textures.at(std::size_t(tex)).source));
    EXPECT_EQ(img.mimeType, "image/png");
    ASSERT_GE(img.bufferView, 0);
    OIIO::Filesystem::IOMemReader mem(const_cast<unsigned char*>(img.image.data()), img.image.size());
    auto in = OIIO::ImageInput::create("png");
    ASSERT_TRUE(in);
    OIIO::ImageSpec config;
    void* proxy = &mem;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    OIIO::ImageSpec spec;
    ASSERT_TRUE(in->open("crate.png", spec, config)) << in->geterror();
    EXPECT_EQ(in->spec().width, 128);
    EXPECT_EQ(in->spec().height, 128);
    // The seams split vertices: more glTF vertices than mesh vertices, one UV each.
    EXPECT_GT(model.accessors.at(std::size_t(prim.attributes.at("TEXCOORD_0"))).count, m->positions.size());

    // And conceptmesh reads it back with its texture.
    const Mesh back = read_mesh(dir / "crate.glb");
    ASSERT_TRUE(back.texture);
    EXPECT_EQ(back.texture->width, 128);
    EXPECT_EQ(back.uvs.size(), back.positions.size());
    EXPECT_EQ(back.colors.size(), back.positions.size());
}

TEST(TexturedWriters, GlbPassesTheKhronosValidator) {
    if (std::system("node --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "node is not installed";
    const fs::path tool = fs::path(CM_BINARY_DIR) / "gltf-validator";
    if (!fs::exists(tool / "node_modules" / "gltf-validator")) {
        fs::create_directories(tool);
        if (!fs::exists(tool / "package.json")) test::write_text(tool / "package.json", "{\"private\": true}\n");
        const std::string cmd = "cd '" + tool.string() +
                                "' && npm install --no-audit --no-fund gltf-validator@latest > '" +
                                (tool / "npm.log").string() + "' 2>&1";
        if (std::system(cmd.c_str()) != 0 || !fs::exists(tool / "node_modules" / "gltf-validator"))
            GTEST_SKIP() << "the npm package gltf-validator could not be installed into " << tool
                         << " (see npm.log there)";
    }
    test::TempDir dir("tex_validator");
    write(textured_box(), dir / "crate.glb");
    test::write_text(
        dir / "validate.js",
        "const v = require('" + (tool / "node_modules" / "gltf-validator").string() +
            "');\n"
            "const buf = require('fs').readFileSync(process.argv[2]);\n"
            "v.validateBytes(new Uint8Array(buf)).then(r => {\n"
            "  console.log('errors=' + r.issues.numErrors + ' warnings=' + r.issues.numWarnings);\n"
            "  for (const m of r.issues.messages) if (m.severity === 0) console.log(m.code + ' ' + m.pointer);\n"
            "}).catch(e => { console.log('failed ' + e); });\n");
    const std::string out = (dir / "report.txt").string();
    const std::string cmd =
        "node '" + (dir / "validate.js").string() + "' '" + (dir / "crate.glb").string() + "' > '" + out + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const std::string report = test::read_text(out);
    EXPECT_NE(report.find("errors=0 "), std::string::npos) << report;
}

// The client a TD opens it in: Blender's own glTF importer (headless), not our reader.
TEST(TexturedWriters, BlenderImportsTheGlbInMetresWithItsNameAndEachSideInItsDrawnColour) {
    if (std::system("blender --version > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "Blender is not installed (Debian's blender package)";
    test::TempDir dir("tex_blender");
    write(textured_box(), dir / "crate.glb", "{height: 2.5}");
    const fs::path log = dir / "blender.log";
    const std::string cmd = "cd '" + dir.path().string() + "' && blender -b --factory-startup --python '" +
                            (fs::path(CM_SOURCE_DIR) / "tests/stages/texture/blender_import.py").string() + "' -- '" +
                            (dir / "crate.glb").string() + "' > '" + log.string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << test::read_text(log);
    const std::string text = test::read_text(log);
    const auto at = text.find("IMPORTED ");
    ASSERT_NE(at, std::string::npos) << text;
    const auto json = nlohmann::json::parse(text.substr(at + 9, text.find('\n', at) - at - 9));
    ASSERT_EQ(json["objects"].size(), 1u) << text;
    const auto& ob = json["objects"][0];
    EXPECT_EQ(ob["name"], "crate"); // what the outliner shows, not a temporary file's name
    EXPECT_EQ(ob["mesh"], "crate");
    // Blender is Z up; the box is as tall as it is wide, 2.5 m.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ob["dimensions"][k].get<double>(), 2.5, 1e-3) << k;
    ASSERT_EQ(ob["uv_layers"].size(), 1u);
    ASSERT_EQ(ob["materials"].size(), 1u);
    EXPECT_EQ(ob["materials"][0]["images"].size(), 1u);
    EXPECT_EQ(ob["colourspace"], "sRGB");
    // Each drawn side (glTF Y up, front +Z) is, in Blender's frame, (x, -z, y); its faces
    // carry the colour of its drawing, as Blender reads the texture.
    const std::vector<View> drawn = box_drawings();
    const test::Rgb colours[3] = {{0.9f, 0.2f, 0.1f}, {0.1f, 0.3f, 0.9f}, {0.2f, 0.8f, 0.3f}};
    int checked[3] = {0, 0, 0};
    for (const auto& f : ob["faces"]) {
        for (int k = 0; k < 3; ++k) {
            const Vec3d n = -drawn[std::size_t(k)].camera.d;
            const Vec3d b(n.x, -n.z, n.y);
            if (f[0].get<double>() * b.x + f[1].get<double>() * b.y + f[2].get<double>() * b.z < 0.99) continue;
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(f[3 + ch].get<double>(), colours[k][std::size_t(ch)], 0.03) << drawn[std::size_t(k)].name;
            ++checked[k];
        }
    }
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(checked[k], 18) << drawn[std::size_t(k)].name; // a 3 x 3 grid, two triangles a square
}

TEST(TexturedWriters, ObjComesWithItsMaterialAndTextureThatOpenMeshAndOpenImageIORead) {
    test::TempDir dir("tex_obj");
    const auto m = textured_box();
    write(m, dir / "crate.obj");
    ASSERT_TRUE(fs::exists(dir / "crate.mtl"));
    ASSERT_TRUE(fs::exists(dir / "crate_basecolor.png"));
    for (const auto& e : fs::directory_iterator(dir.path()))
        EXPECT_EQ(e.path().string().find(".part-"), std::string::npos) << "temporary left: " << e.path();
    const std::string obj = test::read_text(dir / "crate.obj");
    EXPECT_NE(obj.find("mtllib crate.mtl\n"), std::string::npos);
    EXPECT_NE(obj.find("o crate\n"), std::string::npos);
    const std::string mtl = test::read_text(dir / "crate.mtl");
    EXPECT_NE(mtl.find("map_Kd crate_basecolor.png"), std::string::npos) << mtl;

    using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
    OMesh om;
    om.request_halfedge_texcoords2D();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(om, (dir / "crate.obj").string(), opt));
    EXPECT_EQ(om.n_faces(), m->triangles.size());
    EXPECT_EQ(om.n_vertices(), m->positions.size()); // corners carry the UVs, vertices stay shared
    ASSERT_TRUE(opt.check(OpenMesh::IO::Options::FaceTexCoord));
    // Each face's corners carry the UVs written.
    std::size_t f = 0, matched = 0;
    for (auto fh : om.faces()) {
        for (auto heh : om.fh_range(fh)) {
            const auto t = om.texcoord2D(heh);
            const auto vi = std::uint32_t(om.to_vertex_handle(heh).idx());
            for (int k = 0; k < 3; ++k)
                if (m->triangles[f][k] == vi && std::abs(t[0] - m->corner_uvs[3 * f + k][0]) < 1e-5 &&
                    std::abs(t[1] - m->corner_uvs[3 * f + k][1]) < 1e-5)
                    ++matched;
        }
        ++f;
    }
    EXPECT_EQ(matched, 3 * m->triangles.size());

    auto in = OIIO::ImageInput::open((dir / "crate_basecolor.png").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().width, 128);
    EXPECT_EQ(in->spec().nchannels, 3);
}

TEST(TexturedWriters, PlyCarriesTheVertexColoursAsDrawn) {
    test::TempDir dir("tex_ply");
    const auto m = textured_box();
    write(m, dir / "crate.ply");
    using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
    OMesh om;
    om.request_vertex_colors();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexColor;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(om, (dir / "crate.ply").string(), opt));
    ASSERT_TRUE(opt.check(OpenMesh::IO::Options::VertexColor));
    ASSERT_EQ(om.n_vertices(), m->positions.size());
    for (auto vh : om.vertices()) {
        const auto c = om.color(vh);
        const auto& lin = m->colors[std::size_t(vh.idx())];
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], linear_to_srgb(lin[k]) * 255.0f, 1.0f);
    }
}

TEST(TexturedWriters, HeightSizesTheModelInMetresInEveryFormat) {
    test::TempDir dir("tex_units");
    const auto m = textured_box(); // 2 units tall
    for (const char* name : {"tall.glb", "tall.obj", "tall.ply"}) {
        write(m, dir / name, "{height: 1.5}");
        const Mesh back = read_mesh(dir / name);
        Vec3f lo, hi;
        back.bounds(lo, hi);
        EXPECT_NEAR(hi.y - lo.y, 1.5f, 1e-5f) << name;
        EXPECT_NEAR(hi.x - lo.x, 1.5f, 1e-5f) << name; // uniformly
    }
    write(m, dir / "cm.glb", "{unit_scale: 0.01}");
    Vec3f lo, hi;
    read_mesh(dir / "cm.glb").bounds(lo, hi);
    EXPECT_NEAR(hi.y - lo.y, 0.02f, 1e-7f);
    test::StageHarness h("mesh.write");
    h.params("{height: 1.5, unit_scale: 2}").param("path", dir / "x.glb").input("mesh", m);
    EXPECT_NE(h.error().find("height and unit_scale"), std::string::npos) << h.error();
}

TEST(TexturedWriters, CompareReportsTheColourErrorOfATexturedGlbAgainstItsDrawings) {
    test::TempDir dir("tex_compare");
    write(textured_box(), dir / "crate.glb");
    Manifest man;
    man.bounds = {-1, -1, -1, 1, 1, 1};
    for (View v : box_drawings()) {
        if (v.name == "front") test::draw_ink(v, 2); // ink has no fill colour: the no-ink reading leaves it out
        ManifestView mv;
        mv.key = v.name;
        mv.view = v.name;
        mv.image = dir / (v.name + ".png");
        mv.scale = v.camera.scale;
        mv.origin = {v.camera.cx, v.camera.cy};
        write_image(v.image, mv.image);
        man.views.push_back(mv);
    }
    write_manifest(dir / "views.yaml", man);
    const auto r = test::run_cli("compare crate.glb views.yaml --json -q", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("colour")) << r.out;
    ASSERT_EQ(j["colour"].size(), 3u);
    for (const auto& v : j["colour"]) {
        EXPECT_GT(v["pixels"].get<double>(), 1000) << v.dump();
        EXPECT_LT(v["no_ink_mean_delta_e"].get<double>(), 2.0) << v.dump();
        EXPECT_LT(v["no_ink_over10_pct"].get<double>(), 1.0) << v.dump();
        if (v["view"] == "front") {
            // The stroke across the middle: its pixels count as error with ink, not without.
            EXPECT_LT(v["no_ink_pixels"].get<double>(), v["pixels"].get<double>() - 100) << v.dump();
            EXPECT_GT(v["mean_delta_e"].get<double>(), 2.0) << v.dump();
        } else {
            EXPECT_EQ(v["no_ink_pixels"].get<double>(), v["pixels"].get<double>()) << v.dump();
            EXPECT_LT(v["mean_delta_e"].get<double>(), 2.0) << v.dump();
        }
    }
}

namespace {

// Pixels that do not compress to nothing: a gradient with noise, flat blocks, values on the
// rounding edges (k + 0.5) / 255, out of range and NaN, and exact 0 and 1 (alpha 0 and 1 too,
// whichever channel the alpha is).
Image noisy_image(int w, int h, int channels, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-0.03f, 0.03f);
    Image img;
    img.width = w;
    img.height = h;
    img.channels = channels;
    img.pixels.resize(std::size_t(w) * h * channels);
    float* p = img.pixels.data();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < channels; ++k, ++p) {
                const unsigned r = rng();
                if ((x / 40 + y / 30 + k) % 4 == 0) *p = 0.2f * float(k + 1); // flat
                else if (r % 97 == 0) *p = float(r % 256 + 0.5) / 255.0f;     // a rounding edge
                else if (r % 89 == 0) *p = r % 2 ? -0.2f : 1.3f;
                else if (r % 83 == 0) *p = r % 2 ? 0.0f : 1.0f;
                else if (r % 1009 == 0) *p = std::numeric_limits<float>::quiet_NaN();
                else *p = float(x + 2 * y + 17 * k) / float(w + 2 * h + 60) + noise(rng);
            }
    return img;
}

// A preview sheet: flat grey, flat panels, shaded discs with anti-aliased outlines, glyphs.
Image sheet_image(int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.assign(std::size_t(w) * h * 3, 0.5f);
    const auto cover = [](double d) { return float(std::clamp(0.5 - d, 0.0, 1.0)); };
    for (int i = 0; i < 4; ++i) {
        const int x0 = 20 + (i % 2) * (w / 2), y0 = 60 + (i / 2) * (h / 2), x1 = x0 + w / 2 - 40, y1 = y0 + h / 2 - 80;
        const double cx = (x0 + x1) / 2.0, cy = (y0 + y1) / 2.0, radius = (x1 - x0) / 3.0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const double dx = (x + 0.5 - cx) / (1 + 0.3 * i), dy = y + 0.5 - cy;
                const double d = std::sqrt(dx * dx + dy * dy) - radius;
                const float a = cover(d), line = cover(std::abs(d) - 1),
                            shade = float(0.6 + 0.4 * (y - y0) / (y1 - y0));
                float* q = &img.pixels[(std::size_t(y) * w + x) * 3];
                for (int k = 0; k < 3; ++k) {
                    const float fill = (0.3f + 0.2f * float((i + k) % 3)) * shade;
                    q[k] = (1 - line) * (a * fill + (1 - a) * (0.9f + 0.02f * float(k))) + line * 0.1f;
                }
            }
    }
    std::mt19937 rng(7);
    for (int g = 0; g < w / 16; ++g)
        for (int y = 20; y < 34; ++y)
            for (int x = 20 + g * 15; x < 30 + g * 15; ++x)
                if (rng() % 3 == 0)
                    for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * w + x) * 3 + k] = 0.1f;
    return img;
}

// The first `nc` channels through OpenImageIO 2.4's PNG writer (libpng on one thread, level 6
// and its own conversion to 8 bits): what conceptmesh wrote before its own encoder.
std::vector<unsigned char> oiio_png(const Image& img, int nc) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    EXPECT_TRUE(out);
    if (!out) return bytes;
    out->set_ioproxy(&proxy);
    const OIIO::ImageSpec spec(img.width, img.height, nc, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open("memory.png", spec)) << out->geterror();
    EXPECT_TRUE(
        out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data(), OIIO::stride_t(img.channels * sizeof(float))))
        << out->geterror();
    out->close();
    return bytes;
}

// The 8-bit samples of a PNG (bytes in memory, or the file when `file` is not empty) as
// OpenImageIO reads it: alpha as stored (`associate` false) or associated as it gives it.
std::vector<unsigned char> oiio_pixels(const std::vector<unsigned char>& bytes, const fs::path& file, bool associate,
                                       int& w, int& h, int& nc) {
    OIIO::Filesystem::IOMemReader mem(const_cast<unsigned char*>(bytes.data()), bytes.size());
    OIIO::ImageSpec config;
    if (!associate) config.attribute("oiio:UnassociatedAlpha", 1);
    void* proxy = &mem;
    if (file.empty()) config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    auto in = OIIO::ImageInput::open(file.empty() ? "memory.png" : file.string(), &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    w = in->spec().width;
    h = in->spec().height;
    nc = in->spec().nchannels;
    std::vector<unsigned char> px(std::size_t(w) * h * nc);
    EXPECT_TRUE(in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, px.data())) << in->geterror();
    return px;
}

// The chunk types of a PNG in order.
std::vector<std::string> png_chunks(const std::vector<unsigned char>& b) {
    std::vector<std::string> names;
    for (std::size_t at = 8; at + 12 <= b.size();) {
        const std::size_t len =
            std::size_t(b[at]) << 24 | std::size_t(b[at + 1]) << 16 | std::size_t(b[at + 2]) << 8 | b[at + 3];
        names.emplace_back(reinterpret_cast<const char*>(&b[at + 4]), 4);
        at += 12 + len;
    }
    return names;
}

} // namespace

TEST(PngWrite, EverySizeAndChannelCountReadsBackAsOpenImageIOWroteIt) {
    test::TempDir dir("png_write");
    const std::pair<int, int> sizes[] = {{1, 1}, {3, 2}, {17, 5}, {1000, 1150}, {2500, 1300}};
    unsigned seed = 1;
    for (const auto& [w, h] : sizes)
        for (int from : {0, 4}) // an image of nc channels, or the first nc of four
            for (int nc = 1; nc <= 4; ++nc) {
                if (from == 4 && (nc == 4 || w * h > 2'000'000)) continue; // 4 of 4: above; the biggest: time
                SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(nc) + " of " +
                             std::to_string(from ? from : nc) + " channels");
                const Image img = noisy_image(w, h, from ? from : nc, seed++);
                const std::vector<unsigned char> before = oiio_png(img, nc);
                int ew = 0, eh = 0, en = 0;
                const std::vector<unsigned char> expected = oiio_pixels(before, {}, false, ew, eh, en);
                ASSERT_EQ(ew, w);
                ASSERT_EQ(en, nc);

                std::vector<unsigned char> bytes = {'x'}; // appended to
                std::string why;
                std::size_t pieces = 0;
                ASSERT_TRUE(png::write(img, nc, {}, &bytes, why, &pieces)) << why;
                ASSERT_EQ(bytes[0], 'x');
                bytes.erase(bytes.begin());
                const fs::path file = dir / "a.png";
                ASSERT_TRUE(png::write(img, nc, file.string(), nullptr, why)) << why;
                EXPECT_TRUE(test::read_text(file) == std::string(bytes.begin(), bytes.end()));
                // The stream is cut in pieces of 256 kB when there is over 512 kB of it.
                const std::size_t stream = (std::size_t(w) * nc + 1) * h;
                EXPECT_EQ(pieces, stream > 512 * 1024 ? (stream + 256 * 1024 - 1) / (256 * 1024) : 1u);
                EXPECT_EQ(png_chunks(bytes).front(), "IHDR");
                EXPECT_EQ(png_chunks(bytes).back(), "IEND");

                // OpenImageIO reads the samples OpenImageIO wrote, from memory and from the file.
                int gw = 0, gh = 0, gn = 0;
                EXPECT_TRUE(oiio_pixels(bytes, {}, false, gw, gh, gn) == expected);
                EXPECT_EQ(gw, w);
                EXPECT_EQ(gh, h);
                EXPECT_EQ(gn, nc);
                EXPECT_TRUE(oiio_pixels({}, file, false, gw, gh, gn) == expected);
                // conceptmesh's reader gives what OpenImageIO gives (alpha associated), and the
                // same as from the file OpenImageIO wrote.
                const std::vector<unsigned char> associated = oiio_pixels(bytes, {}, true, gw, gh, gn);
                RawImage raw, raw_before;
                ASSERT_TRUE(png::read({}, bytes.data(), bytes.size(), 0, raw, why)) << why;
                ASSERT_TRUE(png::read({}, before.data(), before.size(), 0, raw_before, why)) << why;
                EXPECT_EQ(raw.width, w);
                EXPECT_EQ(raw.channels, nc);
                EXPECT_TRUE(raw.data == associated);
                EXPECT_TRUE(raw.data == raw_before.data);
                RawImage from_file;
                ASSERT_TRUE(png::read(file.string(), nullptr, 0, 0, from_file, why)) << why;
                EXPECT_TRUE(from_file.data == raw.data);
                if (w * h > 1'000'000) { // as small as libpng on one thread would make it
                    EXPECT_LT(std::abs(double(bytes.size()) / double(before.size()) - 1), 0.05)
                        << bytes.size() << " bytes, " << before.size() << " from OpenImageIO";
                }
            }
}

// An 8-bit image holding png_byte() of each float sample (by its place in the row) writes
// the very PNG the float image writes: what the preview sheet relies on to draw in bytes.
TEST(PngWrite, AnImageOfPngBytesWritesTheSamePngAsItsFloats) {
    unsigned seed = 40;
    for (const auto& [w, h] : {std::pair{1, 1}, {3, 2}, {17, 5}, {333, 7}, {1003, 3}})
        for (int nc = 1; nc <= 4; ++nc) {
            SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(nc) + " channels");
            Image img = noisy_image(w, h, nc, seed++);
            // Every rounding edge, just below and above, and what is clamped, in each place of a row.
            const float edges[] = {std::nanf(""), -1.0f, 0.0f, 1.0f, 2.0f, 254.5f / 255.0f, 0.5f / 255.0f};
            for (std::size_t i = 0; i < img.pixels.size(); i += 5) {
                const float e = edges[(i / 5) % 7] + (i % 3 == 0 ? 0.0f : (i % 3 == 1 ? -1e-7f : 1e-7f));
                img.pixels[i] = e;
            }
            for (std::size_t i = 3; i < img.pixels.size(); i += 11)
                img.pixels[i] = std::nextafter(float(i % 256 + 0.5) / 255.0f, i % 2 ? 2.0f : -2.0f);
            Image bytes;
            bytes.width = w;
            bytes.height = h;
            bytes.channels = nc;
            const std::size_t row = std::size_t(w) * nc, tail = row - row % 4;
            for (std::size_t i = 0; i < img.pixels.size(); ++i)
                bytes.bytes.push_back(png_byte(img.pixels[i], i % row >= tail));
            std::vector<unsigned char> a, b;
            std::string why;
            ASSERT_TRUE(png::write(img, nc, {}, &a, why)) << why;
            ASSERT_TRUE(png::write(bytes, nc, {}, &b, why)) << why;
            EXPECT_TRUE(a == b);
            // And an 8-bit image writes the bytes it holds.
            RawImage back;
            ASSERT_TRUE(png::read({}, b.data(), b.size(), 0, back, why)) << why;
            if (nc % 2 == 1) { // no alpha to (un)associate
                EXPECT_TRUE(back.data == bytes.bytes);
            }
        }
}

TEST(PngWrite, ABigImageIsDeflatedInPiecesASmallOneInOne) {
    const Image big = noisy_image(1000, 1150, 3, 7), small = noisy_image(300, 200, 3, 8);
    std::vector<unsigned char> a, b;
    std::string why;
    std::size_t pieces = 0;
    ASSERT_TRUE(png::write(big, 3, {}, &a, why, &pieces)) << why;
    EXPECT_EQ(pieces, 14u); // 3001 x 1150 bytes filtered: 3.3 MB in 256 kB pieces
    ASSERT_TRUE(png::write(small, 3, {}, &b, why, &pieces)) << why;
    EXPECT_EQ(pieces, 1u); // 180 kB: one piece, deflated as by libpng
    // Which cores do the work changes nothing: the pieces follow the size alone.
    std::vector<unsigned char> again;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        ASSERT_TRUE(png::write(big, 3, {}, &again, why, &pieces)) << why;
    }
    EXPECT_TRUE(again == a);
}

TEST(PngWrite, APreviewSheetIsAsSmallAsLibpngMadeIt) {
    const Image sheet = sheet_image(1000, 1150);
    std::vector<unsigned char> bytes;
    std::string why;
    std::size_t pieces = 0;
    ASSERT_TRUE(png::write(sheet, 3, {}, &bytes, why, &pieces)) << why;
    EXPECT_GE(pieces, 2u);
    const std::vector<unsigned char> libpng = oiio_png(sheet, 3); // one thread, level 6
    EXPECT_LT(std::abs(double(bytes.size()) / double(libpng.size()) - 1), 0.05)
        << bytes.size() << " bytes, " << libpng.size() << " from libpng on one thread";
    int w = 0, h = 0, nc = 0;
    EXPECT_TRUE(oiio_pixels(bytes, {}, false, w, h, nc) == oiio_pixels(libpng, {}, false, w, h, nc));
}

TEST(PngWrite, FailuresAreReasonsNotExceptions) {
    const Image img = noisy_image(20, 10, 3, 9);
    std::string why;
    EXPECT_FALSE(png::write(img, 3, "/nonexistent-folder/a.png", nullptr, why));
    EXPECT_EQ(why, "No such file or directory");
    EXPECT_FALSE(png::write(img, 5, {}, nullptr, why));
    EXPECT_EQ(why, "PNG takes 1 to 4 channels of a non-empty image");
    EXPECT_FALSE(png::write(Image{}, 3, {}, nullptr, why));
}
