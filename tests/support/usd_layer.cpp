#include "support/usd_layer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cm::test {

namespace {

// The text of `decl`'s array, between its brackets; npos when absent.
std::size_t array_start(const std::string& layer, const std::string& decl) {
    const std::size_t at = layer.find(decl + " = [");
    return at == std::string::npos ? at : at + decl.size() + 4;
}

std::uint64_t le(const std::string& b, std::size_t at, int bytes) {
    std::uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(b[at + std::size_t(k)]);
    return v;
}

} // namespace

std::vector<double> usd_numbers(const std::string& layer, const std::string& decl) {
    std::vector<double> out;
    std::size_t at = array_start(layer, decl);
    if (at == std::string::npos) return out;
    const std::size_t end = layer.find(']', at);
    while (at < end) {
        const char c = layer[at];
        if (c == '(' || c == ')' || c == ',' || c == ' ') {
            ++at;
            continue;
        }
        char* stop = nullptr;
        out.push_back(std::strtod(layer.c_str() + at, &stop));
        const std::size_t next = std::size_t(stop - layer.c_str());
        if (next == at) {
            ADD_FAILURE() << decl << ": not a number at \"" << layer.substr(at, 20) << "\"";
            break;
        }
        at = next;
    }
    return out;
}

bool usd_has(const std::string& layer, const std::string& decl) { return layer.find(decl) != std::string::npos; }

std::string usd_value(const std::string& layer, const std::string& key) {
    for (std::size_t at = layer.find(key + " = "); at != std::string::npos; at = layer.find(key + " = ", at + 1)) {
        if (at > 0 && layer[at - 1] != ' ' && layer[at - 1] != '\n') continue;
        const std::size_t from = at + key.size() + 3;
        return layer.substr(from, layer.find('\n', from) - from);
    }
    return {};
}

Mesh usd_mesh(const std::string& layer) {
    Mesh m;
    const std::vector<double> p = usd_numbers(layer, "point3f[] points");
    for (std::size_t i = 0; i + 2 < p.size(); i += 3)
        m.positions.push_back({float(p[i]), float(p[i + 1]), float(p[i + 2])});
    const std::vector<double> idx = usd_numbers(layer, "int[] faceVertexIndices");
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3)
        m.triangles.push_back({std::uint32_t(idx[i]), std::uint32_t(idx[i + 1]), std::uint32_t(idx[i + 2])});
    for (double n : usd_numbers(layer, "int[] faceVertexCounts")) EXPECT_EQ(n, 3.0);
    return m;
}

std::vector<ZipFile> read_zip(const std::string& b) {
    std::vector<ZipFile> files;
    // The end record closes the archive (no comment is written).
    if (b.size() < 22 || le(b, b.size() - 22, 4) != 0x06054b50) {
        ADD_FAILURE() << "no zip end record at the end";
        return files;
    }
    const std::size_t count = le(b, b.size() - 12, 2);
    std::size_t at = le(b, b.size() - 6, 4);
    for (std::size_t i = 0; i < count; ++i) {
        if (at + 46 > b.size() || le(b, at, 4) != 0x02014b50) {
            ADD_FAILURE() << "central directory entry " << i << " is not where the directory says";
            break;
        }
        ZipFile f;
        f.method = int(le(b, at + 10, 2));
        f.crc = std::uint32_t(le(b, at + 16, 4));
        const std::size_t size = le(b, at + 20, 4), name = le(b, at + 28, 2);
        const std::size_t extra = le(b, at + 30, 2), comment = le(b, at + 32, 2);
        f.header_offset = le(b, at + 42, 4);
        f.name = b.substr(at + 46, name);
        EXPECT_EQ(le(b, at + 24, 4), size) << f.name << ": stored, so its two sizes agree";
        at += 46 + name + extra + comment;
        const std::size_t h = f.header_offset;
        if (h + 30 > b.size() || le(b, h, 4) != 0x04034b50) {
            ADD_FAILURE() << f.name << ": no local header at " << h;
            break;
        }
        EXPECT_EQ(b.substr(h + 30, le(b, h + 26, 2)), f.name);
        EXPECT_EQ(le(b, h + 14, 4), f.crc) << f.name << ": local and central CRC";
        f.data_offset = h + 30 + le(b, h + 26, 2) + le(b, h + 28, 2);
        f.data = b.substr(f.data_offset, size);
        files.push_back(std::move(f));
    }
    return files;
}

fs::path usd_readers(std::string& why) {
    if (std::system("node --version > /dev/null 2>&1") != 0) {
        why = "node is not installed";
        return {};
    }
    const fs::path dir = fs::path(CM_BINARY_DIR) / "usd-readers";
    const auto installed = [&] {
        return fs::exists(dir / "node_modules/tinyusdz/tinyusdz.wasm") &&
               fs::exists(dir / "node_modules/three/examples/jsm/loaders/USDLoader.js");
    };
    if (!installed()) {
        fs::create_directories(dir);
        const std::string cmd = "sh '" + (source_dir() / "tests/support/usd_readers/install.sh").string() + "' '" +
                                dir.string() + "' > '" + (dir / "npm.log").string() + "' 2>&1";
        if (std::system(cmd.c_str()) != 0 || !installed()) {
            why = "the npm packages tinyusdz and three could not be installed into " + dir.string() +
                  " (see npm.log there)";
            return {};
        }
    }
    return dir / "node_modules";
}

nlohmann::json run_usd_reader(const fs::path& modules, const std::string& script, const fs::path& file,
                              const std::string& tag, const std::string& extra) {
    const fs::path out = file.parent_path() / (file.filename().string() + "." + script + ".txt");
    const std::string cmd = "node '" + (source_dir() / "tests/support/usd_readers" / script).string() + "' '" +
                            modules.string() + "' '" + file.string() + "' " + extra + " > '" + out.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    const std::string text = read_text(out);
    const std::size_t at = text.find(tag + " ");
    if (status != 0 || at == std::string::npos) {
        ADD_FAILURE() << script << " on " << file << " failed:\n" << text;
        return nlohmann::json::object();
    }
    const std::size_t from = at + tag.size() + 1;
    return nlohmann::json::parse(text.substr(from, text.find('\n', from) - from));
}

} // namespace cm::test
