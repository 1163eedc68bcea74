// What flows along the edges of a pipeline graph.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace cm {

struct Views;
struct Volume;
struct Mesh;

/// A file (or files) a stage wrote; the host commits them when the run succeeds.
struct FileOutput {
    std::vector<std::filesystem::path> paths;
};

/// A temporary name beside `final_path`, unique in this process and across processes
/// ("<final>.part-<pid>-<n><ext>": the extension stays, so writers that pick a format
/// from it still work). Files are written there and renamed when the run succeeds.
std::filesystem::path temporary_path(const std::filesystem::path& final_path);

/// The extension of `path` in lower case (".png"), for formats picked by it.
std::string lower_extension(const std::filesystem::path& path);

/// A stage's findings (e.g. silhouette error), as JSON text merged into the run report.
struct Report {
    std::string json; ///< a JSON object
};

enum class DataKind { Views, Volume, Mesh, File, Report };
const char* to_string(DataKind k);

using Data =
    std::variant<std::monostate, std::shared_ptr<const Views>, std::shared_ptr<const Volume>,
                 std::shared_ptr<const Mesh>, std::shared_ptr<const FileOutput>, std::shared_ptr<const Report>>;

/// The kind held by a Data; throws cm::Error for an empty one.
DataKind kind_of(const Data& d);

} // namespace cm
