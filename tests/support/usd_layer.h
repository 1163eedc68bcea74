// Reading back what the USD writer wrote, for the tests, without a USD library: the values
// of a .usda layer's text, the files of a .usdz package, and the two npm readers (TinyUSDZ,
// three.js's USDLoader) run through node on a written file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mesh.h"

namespace cm::test {

/// The numbers of the array attribute declared as `decl` ("point3f[] points"), tuples
/// flattened; empty when the layer has no such attribute.
std::vector<double> usd_numbers(const std::string& layer, const std::string& decl);
/// True when the layer declares `decl`.
bool usd_has(const std::string& layer, const std::string& decl);
/// The text after `key = ` up to the end of its line ("\"Y\"", "1"), the first such line;
/// empty when there is none.
std::string usd_value(const std::string& layer, const std::string& key);
/// The mesh the layer's points and faceVertexIndices describe (faceVertexCounts all 3).
Mesh usd_mesh(const std::string& layer);

/// One file of a zip archive, as its central directory and local header describe it.
struct ZipFile {
    std::string name;
    int method = -1;
    std::uint32_t crc = 0;
    std::uint64_t header_offset = 0, data_offset = 0;
    std::string data;
};
/// The files of a zip archive in the order of its central directory; fails the test (and
/// returns what it read) on a malformed archive.
std::vector<ZipFile> read_zip(const std::string& bytes);

/// The folder holding node_modules with the two npm USD readers, installed there when
/// missing (tests/support/usd_readers/install.sh); empty, with `why` set, when node
/// or the packages cannot be had: the caller skips with `why`.
std::filesystem::path usd_readers(std::string& why);
/// Runs tests/support/usd_readers/<script> (tinyusdz_load.mjs, three_load.mjs) on
/// `file` and returns the JSON it printed after `tag` ("TINYUSDZ", "THREE"); fails the test
/// with the script's output when there is none.
nlohmann::json run_usd_reader(const std::filesystem::path& modules, const std::string& script,
                              const std::filesystem::path& file, const std::string& tag, const std::string& extra = {});

} // namespace cm::test
