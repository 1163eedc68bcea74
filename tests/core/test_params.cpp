#include <gtest/gtest.h>

#include <unistd.h>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/params.h"

using namespace cm;

TEST(Params, TextParsingFollowsTheDeclaredType) {
    const auto i = ParamSpec::Int("resolution", 256, 8, 16384, "cells", "cells along the longest side");
    EXPECT_EQ(std::get<std::int64_t>(parse_param_text(i, "512")), 512);
    EXPECT_THROW(parse_param_text(i, "12.5"), Error);
    EXPECT_THROW(parse_param_text(i, "abc"), Error);
    const auto f = ParamSpec::Float("factor", 0.5, 0, 1, "", "");
    EXPECT_DOUBLE_EQ(std::get<double>(parse_param_text(f, "0.25")), 0.25);
    EXPECT_THROW(parse_param_text(f, "nan"), Error);
    const auto b = ParamSpec::Bool("binary", true, "");
    EXPECT_FALSE(std::get<bool>(parse_param_text(b, "false")));
    EXPECT_THROW(parse_param_text(b, "maybe"), Error);
}

TEST(Params, RangeAndChoiceChecksNameTheParameter) {
    const auto i = ParamSpec::Int("resolution", 256, 8, 16384, "cells", "");
    EXPECT_EQ(check_param(i, ParamValue(std::int64_t(3))), "resolution must be in [8, 16384] cells, got 3");
    EXPECT_EQ(check_param(i, ParamValue(std::int64_t(8))), "");
    const auto e = ParamSpec::Enum("keep", "auto", {"auto", "all"}, "");
    EXPECT_NE(check_param(e, ParamValue(std::string("some"))).find("one of auto, all"), std::string::npos);
}

TEST(Params, SchemaCarriesTypeRangeDefaultAndUnit) {
    const auto j = param_schema(ParamSpec::Int("resolution", 256, 8, 16384, "cells", "cells along the longest side"));
    EXPECT_EQ(j["type"], "integer");
    EXPECT_EQ(j["minimum"], 8);
    EXPECT_EQ(j["maximum"], 16384);
    EXPECT_EQ(j["default"], 256);
    EXPECT_EQ(j["x-unit"], "cells");
}

TEST(Params, OutputPathChecksTheExtensionAndTheFolders) {
    const auto many = ParamSpec::OutputPath("path", {".obj", ".ply", ".glb"}, "output file");
    EXPECT_TRUE(many.is_output);
    EXPECT_EQ(param_schema(many)["format"], "path");
    EXPECT_EQ(check_output_path(many, "x.abc"), "path \"x.abc\" has an unknown extension (use .obj, .ply or .glb)");
    EXPECT_EQ(check_output_path(many, "X.PLY"), "");
    const auto one = ParamSpec::OutputPath("sheet", {".png"}, "output image");
    EXPECT_EQ(check_output_path(one, "a.jpg"), "sheet \"a.jpg\" must end in .png");
    // Missing folders are fine (the run makes them); a file where a folder must be is not.
    const auto dir = std::filesystem::temp_directory_path() / ("cm-output-path-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    { std::ofstream(dir / "file") << "x"; }
    EXPECT_EQ(check_output_path(one, dir / "new" / "deeper" / "a.png"), "");
    EXPECT_EQ(
        check_output_path(one, dir / "file" / "a.png"),
        "sheet \"" + (dir / "file" / "a.png").string() + "\": \"" + (dir / "file").string() + "\" is not a folder");
    std::filesystem::remove_all(dir);
}
