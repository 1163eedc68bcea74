#include "io/gltf_io.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <unordered_map>

#define TINYGLTF_IMPLEMENTATION
#include "io/tinygltf_config.h"

#include "core/error.h"
#include "core/views.h"
#include "io/image_io.h"
#include "io/progress_stream.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// Adds `item` to one of the model's lists; returns its index there, by which glTF refers to it.
template <typename T>
int add(std::vector<T>& list, T item) {
    list.push_back(std::move(item));
    return int(list.size() - 1);
}

template <typename T>
int append(tinygltf::Model& model, const std::vector<T>& data, int target) {
    auto& buf = model.buffers[0].data;
    while (buf.size() % 4) buf.push_back(0);
    const std::size_t offset = buf.size();
    const std::size_t bytes = data.size() * sizeof(T);
    buf.resize(offset + bytes);
    if (bytes) std::memcpy(buf.data() + offset, data.data(), bytes);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = bytes;
    view.target = target;
    return add(model.bufferViews, view);
}

int accessor(tinygltf::Model& model, int view, int component, int type, std::size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    return add(model.accessors, a);
}

// The vertices as glTF needs them: one per distinct (vertex, corner UV) pair when the
// mesh has per-corner UVs (an atlas seam splits a vertex), else the mesh's own.
struct GltfVertices {
    std::vector<std::uint32_t> source;    ///< mesh vertex of each glTF vertex
    std::vector<std::array<float, 2>> uv; ///< v up; empty without UVs
    std::vector<std::uint32_t> indices;   ///< 3 per triangle
};

GltfVertices gltf_vertices(const Mesh& mesh) {
    GltfVertices g;
    g.indices.resize(mesh.triangles.size() * 3);
    if (mesh.corner_uvs.size() == mesh.triangles.size() * 3) {
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> seen; // mesh vertex -> its glTF vertices
        for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = mesh.triangles[f][k];
                const auto& uv = mesh.corner_uvs[3 * f + k];
                auto& list = seen[v];
                std::uint32_t found = 0xffffffffu;
                for (std::uint32_t c : list)
                    if (g.uv[c] == uv) found = c;
                if (found == 0xffffffffu) {
                    found = std::uint32_t(g.source.size());
                    g.source.push_back(v);
                    g.uv.push_back(uv);
                    list.push_back(found);
                }
                g.indices[3 * f + k] = found;
            }
        return g;
    }
    g.source.resize(mesh.positions.size());
    for (std::size_t i = 0; i < g.source.size(); ++i) g.source[i] = std::uint32_t(i);
    if (mesh.uvs.size() == mesh.positions.size()) g.uv = mesh.uvs;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) g.indices[3 * f + k] = mesh.triangles[f][k];
    return g;
}

// The base-colour texture as an embedded PNG and a PBR material (roughness 1, metallic 0:
// painted colour, no shine); returns the material's index.
int add_material(tinygltf::Model& model, const Mesh& mesh, const std::string& name) {
    tinygltf::Material mat;
    mat.name = name;
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 1.0;
    mat.doubleSided = false;
    if (mesh.texture && !mesh.texture->empty()) {
        const std::vector<unsigned char> png = encode_png(*mesh.texture, 3);
        tinygltf::Image img;
        img.name = name + "_basecolor";
        img.mimeType = "image/png";
        img.bufferView = append(model, png, 0);
        tinygltf::Sampler sampler;
        sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
        sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
        sampler.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        tinygltf::Texture tex;
        tex.source = add(model.images, img);
        tex.sampler = add(model.samplers, sampler);
        mat.pbrMetallicRoughness.baseColorTexture.index = add(model.textures, tex);
    }
    return add(model.materials, mat);
}

} // namespace

void write_glb(const Mesh& mesh, const fs::path& file, bool normals, const std::string& name_in, Progress progress) {
    // Gathering the buffers is about a third of the time; the file goes out in chunks.
    const Progress build = progress.part(0, 0.3);
    if (build) build(0);
    const std::string name = name_in.empty() ? file.stem().string() : name_in;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "conceptmesh";
    model.buffers.emplace_back();
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    const GltfVertices gv = gltf_vertices(mesh);
    const std::size_t nv = gv.source.size();

    std::vector<float> pos(nv * 3);
    std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < nv; ++i)
        for (int k = 0; k < 3; ++k) {
            const float v = mesh.positions[gv.source[i]][k];
            pos[3 * i + k] = v;
            lo[k] = std::min(lo[k], double(v));
            hi[k] = std::max(hi[k], double(v));
        }
    const int pa = accessor(model, append(model, pos, TINYGLTF_TARGET_ARRAY_BUFFER), TINYGLTF_COMPONENT_TYPE_FLOAT,
                            TINYGLTF_TYPE_VEC3, nv);
    model.accessors[pa].minValues = lo;
    model.accessors[pa].maxValues = hi;
    prim.attributes["POSITION"] = pa;
    if (build) build(0.4);

    if (normals && mesh.normals.size() == mesh.positions.size()) {
        std::vector<float> n(nv * 3);
        for (std::size_t i = 0; i < nv; ++i)
            for (int k = 0; k < 3; ++k) n[3 * i + k] = mesh.normals[gv.source[i]][k];
        prim.attributes["NORMAL"] = accessor(model, append(model, n, TINYGLTF_TARGET_ARRAY_BUFFER),
                                             TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, nv);
    }
    if (gv.uv.size() == nv) {
        std::vector<float> t(nv * 2);
        for (std::size_t i = 0; i < nv; ++i) {
            t[2 * i] = gv.uv[i][0];
            t[2 * i + 1] = 1.0f - gv.uv[i][1];
        }
        prim.attributes["TEXCOORD_0"] = accessor(model, append(model, t, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                 TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, nv);
    }
    const bool textured = mesh.texture && !mesh.texture->empty() && gv.uv.size() == nv;
    if (mesh.colors.size() == mesh.positions.size()) {
        std::vector<float> c(nv * 4);
        for (std::size_t i = 0; i < nv; ++i)
            for (int k = 0; k < 4; ++k) c[4 * i + k] = mesh.colors[gv.source[i]][k];
        // COLOR_0 multiplies the base-colour texture in every viewer; beside a texture the
        // vertex colours travel as an application attribute that leaves the look alone.
        prim.attributes[textured ? "_COLOR_0" : "COLOR_0"] =
            accessor(model, append(model, c, TINYGLTF_TARGET_ARRAY_BUFFER), TINYGLTF_COMPONENT_TYPE_FLOAT,
                     TINYGLTF_TYPE_VEC4, nv);
    }
    if (textured || mesh.colors.size() == mesh.positions.size()) {
        Mesh bare; // a material without a texture when there is nothing for it to address
        prim.material = add_material(model, textured ? mesh : bare, name);
    }
    if (build) build(0.8);
    const std::vector<std::uint32_t>& idx = gv.indices;
    prim.indices = accessor(model, append(model, idx, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, idx.size());

    tinygltf::Mesh gm;
    gm.name = name;
    gm.primitives.push_back(prim);
    model.meshes.push_back(gm);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = gm.name;
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    tinygltf::TinyGLTF io;
    ProgressFileStream out(file, model.buffers[0].data.size() + 4096, progress.part(0.3, 1.0));
    if (!out.is_open()) throw Error("cannot write mesh \"" + file.string() + "\": " + std::strerror(errno));
    const bool wrote = io.WriteGltfSceneToStream(&model, out, false, true);
    if (!out.finish() || !wrote) throw Error("cannot write mesh \"" + file.string() + "\": " + std::strerror(errno));
}

namespace {

using Mat4 = std::array<double, 16>; // column-major, as glTF

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat4 mul(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr)
            for (int k = 0; k < 4; ++k) r[c * 4 + rr] += a[k * 4 + rr] * b[c * 4 + k];
    return r;
}
Mat4 local_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        Mat4 m;
        std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
        return m;
    }
    Mat4 t = identity(), r = identity(), s = identity();
    if (n.translation.size() == 3) {
        t[12] = n.translation[0];
        t[13] = n.translation[1];
        t[14] = n.translation[2];
    }
    if (n.rotation.size() == 4) {
        const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
        r = {1 - 2 * (y * y + z * z),
             2 * (x * y + z * w),
             2 * (x * z - y * w),
             0,
             2 * (x * y - z * w),
             1 - 2 * (x * x + z * z),
             2 * (y * z + x * w),
             0,
             2 * (x * z + y * w),
             2 * (y * z - x * w),
             1 - 2 * (x * x + y * y),
             0,
             0,
             0,
             0,
             1};
    }
    if (n.scale.size() == 3) {
        s[0] = n.scale[0];
        s[5] = n.scale[1];
        s[10] = n.scale[2];
    }
    return mul(t, mul(r, s));
}

// Reads accessor `index` as doubles, `comps` per element (normalised integers scaled to [0,1]).
std::vector<double> read_accessor(const tinygltf::Model& model, int index, int comps, const std::string& what) {
    const auto& a = model.accessors.at(std::size_t(index));
    if (a.bufferView < 0) return std::vector<double>(a.count * std::size_t(comps), 0.0);
    const auto& view = model.bufferViews.at(std::size_t(a.bufferView));
    const auto& buf = model.buffers.at(std::size_t(view.buffer));
    const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType));
    const int ncomp = tinygltf::GetNumComponentsInType(std::uint32_t(a.type));
    if (csize <= 0 || ncomp != comps) throw Error(what + " has an unexpected type");
    const std::size_t stride = view.byteStride ? view.byteStride : std::size_t(csize * ncomp);
    const std::size_t base = view.byteOffset + a.byteOffset;
    if (a.count && base + stride * (a.count - 1) + std::size_t(csize * ncomp) > buf.data.size())
        throw Error(what + " runs past the end of its buffer");
    std::vector<double> out(a.count * std::size_t(comps));
    for (std::size_t i = 0; i < a.count; ++i)
        for (int k = 0; k < comps; ++k) {
            const unsigned char* p = buf.data.data() + base + i * stride + std::size_t(k * csize);
            double v = 0;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float f;
                std::memcpy(&f, p, 4);
                v = f;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                v = u;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                v = a.normalized ? u / 65535.0 : u;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = a.normalized ? *p / 255.0 : *p; break;
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                std::int16_t u;
                std::memcpy(&u, p, 2);
                v = u;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_BYTE: v = double(static_cast<signed char>(*p)); break;
            default: throw Error(what + " has an unsupported component type");
            }
            out[i * std::size_t(comps) + std::size_t(k)] = v;
        }
    return out;
}

// Keeps an embedded image as 8-bit RGBA for the reader below (decoded by OpenImageIO).
bool load_image(tinygltf::Image* image, const int, std::string* err, std::string*, int, int, const unsigned char* bytes,
                int size, void*) {
    try {
        const Image img = decode_image(bytes, std::size_t(size), "image \"" + image->name + "\"");
        image->width = img.width;
        image->height = img.height;
        image->component = 4;
        image->bits = 8;
        image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        image->image.resize(img.pixels.size());
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            image->image[i] = static_cast<unsigned char>(std::clamp(img.pixels[i], 0.0f, 1.0f) * 255.0f + 0.5f);
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

// The base-colour texture of a material, as float RGBA; null when it has none.
std::shared_ptr<const Image> base_colour(const tinygltf::Model& model, int material) {
    if (material < 0 || std::size_t(material) >= model.materials.size()) return nullptr;
    const int t = model.materials[std::size_t(material)].pbrMetallicRoughness.baseColorTexture.index;
    if (t < 0 || std::size_t(t) >= model.textures.size()) return nullptr;
    const int s = model.textures[std::size_t(t)].source;
    if (s < 0 || std::size_t(s) >= model.images.size()) return nullptr;
    const tinygltf::Image& gi = model.images[std::size_t(s)];
    if (gi.image.empty() || gi.component != 4 || gi.bits != 8) return nullptr;
    auto img = std::make_shared<Image>();
    img->width = gi.width;
    img->height = gi.height;
    img->channels = 4;
    img->pixels.resize(gi.image.size());
    for (std::size_t i = 0; i < gi.image.size(); ++i) img->pixels[i] = float(gi.image[i]) / 255.0f;
    return img;
}

} // namespace

Mesh read_glb(const fs::path& file) {
    tinygltf::Model model;
    tinygltf::TinyGLTF io;
    io.SetImageLoader(&load_image, nullptr);
    std::string err, warn;
    const bool ok = file.extension() == ".gltf" ? io.LoadASCIIFromFile(&model, &err, &warn, file.string())
                                                : io.LoadBinaryFromFile(&model, &err, &warn, file.string());
    if (!ok) throw Error("cannot read mesh \"" + file.string() + "\": " + (err.empty() ? "not a glTF file" : err));
    const std::string where = "cannot read mesh \"" + file.string() + "\": ";
    Mesh m;
    bool all_normals = true, all_uvs = true, all_colors = true;
    auto add_mesh = [&](int mesh_index, const Mat4& M) {
        const auto& gm = model.meshes.at(std::size_t(mesh_index));
        for (const auto& prim : gm.primitives) {
            if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
            auto it = prim.attributes.find("POSITION");
            if (it == prim.attributes.end()) continue;
            const auto p = read_accessor(model, it->second, 3, where + "POSITION");
            const std::size_t n = p.size() / 3;
            const std::uint32_t base = std::uint32_t(m.positions.size());
            for (std::size_t i = 0; i < n; ++i) {
                const double x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
                m.positions.emplace_back(float(M[0] * x + M[4] * y + M[8] * z + M[12]),
                                         float(M[1] * x + M[5] * y + M[9] * z + M[13]),
                                         float(M[2] * x + M[6] * y + M[10] * z + M[14]));
            }
            auto nit = prim.attributes.find("NORMAL");
            if (nit != prim.attributes.end() && all_normals) {
                const auto nn = read_accessor(model, nit->second, 3, where + "NORMAL");
                for (std::size_t i = 0; i < n; ++i) {
                    const double x = nn[3 * i], y = nn[3 * i + 1], z = nn[3 * i + 2];
                    // Normals go through the inverse transpose; for rotations and uniform scales
                    // the linear part, renormalised, is the same.
                    m.normals.push_back(
                        Vec3f(normalize(Vec3d(M[0] * x + M[4] * y + M[8] * z, M[1] * x + M[5] * y + M[9] * z,
                                              M[2] * x + M[6] * y + M[10] * z))));
                }
            } else {
                all_normals = false;
            }
            auto tit = prim.attributes.find("TEXCOORD_0");
            if (tit != prim.attributes.end() && all_uvs) {
                const auto t = read_accessor(model, tit->second, 2, where + "TEXCOORD_0");
                for (std::size_t i = 0; i < n; ++i) m.uvs.push_back({float(t[2 * i]), float(1.0 - t[2 * i + 1])});
            } else {
                all_uvs = false;
            }
            if (!m.texture) m.texture = base_colour(model, prim.material);
            auto cit = prim.attributes.find("COLOR_0");
            if (cit == prim.attributes.end()) cit = prim.attributes.find("_COLOR_0");
            if (cit != prim.attributes.end() && all_colors) {
                const int comps =
                    tinygltf::GetNumComponentsInType(std::uint32_t(model.accessors.at(std::size_t(cit->second)).type));
                if (comps != 3 && comps != 4) throw Error(where + "COLOR_0 has an unexpected type");
                const auto c = read_accessor(model, cit->second, comps, where + "COLOR_0");
                for (std::size_t i = 0; i < n; ++i)
                    m.colors.push_back({float(c[i * comps]), float(c[i * comps + 1]), float(c[i * comps + 2]),
                                        comps == 4 ? float(c[i * comps + 3]) : 1.0f});
            } else {
                all_colors = false;
            }
            std::vector<double> idx;
            if (prim.indices >= 0) {
                idx = read_accessor(model, prim.indices, 1, where + "indices");
            } else {
                idx.resize(n);
                for (std::size_t i = 0; i < n; ++i) idx[i] = double(i);
            }
            for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
                std::array<std::uint32_t, 3> t;
                for (int k = 0; k < 3; ++k) {
                    if (idx[i + k] >= double(n)) throw Error(where + "a face index is out of range");
                    t[k] = base + std::uint32_t(idx[i + k]);
                }
                m.triangles.push_back(t);
            }
        }
    };
    std::function<void(int, const Mat4&)> visit = [&](int node, const Mat4& parent) {
        const auto& n = model.nodes.at(std::size_t(node));
        const Mat4 M = mul(parent, local_matrix(n));
        if (n.mesh >= 0) add_mesh(n.mesh, M);
        for (int c : n.children) visit(c, M);
    };
    if (!model.scenes.empty()) {
        const auto& scene = model.scenes[std::size_t(std::max(0, model.defaultScene))];
        for (int n : scene.nodes) visit(n, identity());
    } else {
        for (std::size_t i = 0; i < model.meshes.size(); ++i) add_mesh(int(i), identity());
    }
    if (!all_normals) m.normals.clear();
    if (!all_uvs) m.uvs.clear();
    if (!all_colors) m.colors.clear();
    if (m.triangles.empty()) throw Error(where + "it has no triangles");
    return m;
}

} // namespace cm
