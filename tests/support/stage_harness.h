// Runs one stage by name the way a pipeline node runs, for the tests: the parameters,
// written as YAML, are checked against the stage's declaration and configure a new
// stage (configure_stage()), which then runs on the inputs given and has its files
// committed (run_stage()). Messages are those of a pipeline file without its
// "file:line: node "id" (stage): " prefix.
//
//     test::StageHarness h("mesh.reduce");
//     h.params("{max_angle_deg: 20, target_ratio: 0.1}").input("mesh", sphere);
//     auto out = h.run<Mesh>();
//     EXPECT_TRUE(h.warnings().empty());
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/stage.h"
#include "pipeline/run_stage.h"
#include "plugins/registry.h"

namespace cm::test {

class StageHarness {
public:
    /// `stage` from the plugins built next to the command (Registry::global(): the tests
    /// run beside it, with CONCEPTMESH_PLUGIN_PATH empty).
    explicit StageHarness(std::string stage);
    /// `stage` from `registry` (e.g. one that also holds the test stages).
    StageHarness(std::string stage, const Registry& registry);
    /// Removes what keep_staged() left under temporary names.
    ~StageHarness();
    StageHarness(const StageHarness&) = delete;
    StageHarness& operator=(const StageHarness&) = delete;

    /// Adds the parameters of a YAML mapping ("{resolution: 64, keep: all}"), typed as in
    /// a pipeline file; a name given again replaces its earlier value.
    StageHarness& params(const std::string& yaml_mapping);
    /// One parameter: a number or a boolean as a plain scalar, text and paths quoted.
    template <typename T>
    StageHarness& param(const std::string& name, const T& value) {
        return params("{" + name + ": " + yaml_scalar(value) + "}");
    }
    /// Connects `port` to `data`: a Mesh, Views, Volume, ... by value or shared_ptr.
    template <typename T>
    StageHarness& input(const std::string& port, std::shared_ptr<T> data) {
        inputs_.set(port, Data(std::shared_ptr<const T>(std::move(data))));
        return *this;
    }
    template <typename T>
    StageHarness& input(const std::string& port, T data) {
        return input(port, std::make_shared<const T>(std::move(data)));
    }
    /// Where side outputs go (Context::side_output_dir()).
    StageHarness& side_output_dir(const std::filesystem::path& dir);
    /// Leaves the files the stage writes under their temporary names (staged()) instead
    /// of committing them, as a pipeline does until every node has succeeded.
    StageHarness& keep_staged();

    StageInfo info() const;
    /// Resolves the parameters and configures a new stage with them, without running it.
    /// Throws cm::Error.
    void configure() const;
    /// Configures a new stage, runs it and commits its files. Throws cm::Error (cm::Cancelled)
    /// as the stage does; a failed run leaves the results of the last good one.
    Data run_data();
    /// run_data(), holding a T (Mesh, Views, Volume, FileOutput, Report).
    template <typename T>
    std::shared_ptr<const T> run() {
        Data d = run_data();
        auto* p = std::get_if<std::shared_ptr<const T>>(&d);
        if (!p || !*p) throw Error("stage \"" + stage_ + "\" returned another kind of data");
        return *p;
    }
    /// Runs as run_data() does; the message of the cm::Error it throws, "" when it succeeds.
    std::string error();

    /// Of the last run that succeeded:
    const std::map<std::string, std::string>& metrics() const { return last_.metrics_json; } ///< name -> JSON
    double metric(const std::string& name) const; ///< a number among metrics()
    const std::vector<std::string>& warnings() const { return last_.warnings; }
    const std::vector<std::filesystem::path>& outputs() const { return last_.outputs; } ///< files committed
    /// Temporary name -> final name of every file written (kept by keep_staged()).
    const std::vector<std::pair<std::filesystem::path, std::filesystem::path>>& staged() const { return last_.staged; }

private:
    template <typename T>
    static std::string yaml_scalar(const T& value) {
        if constexpr (std::is_same_v<T, bool>) {
            return value ? "true" : "false";
        } else if constexpr (std::is_arithmetic_v<T>) {
            std::ostringstream s;
            s.precision(17);
            s << value;
            return s.str();
        } else {
            return quoted(std::filesystem::path(value).string());
        }
    }
    static std::string quoted(const std::string& text);
    void remove_staged();

    std::string stage_;
    const Registry& registry_;
    std::map<std::string, RawParam> params_;
    Inputs inputs_;
    StageRunOptions opt_;
    StageRun last_;
};

} // namespace cm::test
