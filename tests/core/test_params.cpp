#include <gtest/gtest.h>

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
