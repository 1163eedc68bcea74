// Declared parameters bound to members: configure() fills them, typed, from the checked
// values, and info() lists the declarations they came from.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/error.h"
#include "core/stage.h"

using namespace cm;

namespace {

class Bound : public Stage {
public:
    enum class Mode { Fast, Exact };
    Param<int> count;
    double scale = 0;
    std::optional<double> limit;
    std::filesystem::path file;
    Mode mode = Mode::Fast;
    int checks = 0;

    StageSignature signature() const override { return {"test.bound", "binds one of each", {}, DataKind::Mesh}; }
    void declare(ParamBinder& b) override {
        b.add(count, ParamSpec::Int("count", 3, 1, 10, "", "how many"));
        b.add(scale, ParamSpec::Float("scale", 0.5, 0.0, 1.0, "", "how much"));
        b.add(limit, ParamSpec::Float("limit", 1.0, 0.0, 9.0, "", "a bound when set").optional());
        b.add(file, ParamSpec::Path("file", std::nullopt, "which file"));
        b.add(mode, ParamSpec::Enum("mode", "fast", {"fast", "exact"}, "how"), {Mode::Fast, Mode::Exact});
    }
    void check() override {
        ++checks;
        if (mode == Mode::Exact && scale > 0.9) throw Error("exact needs a scale up to 0.9");
    }
    Data run(const Inputs&, Context&) override { return {}; }
};

template <typename Member>
class Misbound : public Stage {
public:
    Member member{};
    ParamSpec spec;
    explicit Misbound(ParamSpec s) : spec(std::move(s)) {}
    StageSignature signature() const override { return {"test.misbound", "", {}, DataKind::Mesh}; }
    void declare(ParamBinder& b) override { b.add(member, spec); }
    Data run(const Inputs&, Context&) override { return {}; }
};

ParamSet with_file() {
    ParamSet p;
    p.set("file", std::string("a.txt"));
    return p;
}

std::string error_of(Stage& s, const ParamSet& p) {
    try {
        s.configure(p);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(ParamBinder, InfoListsTheDeclarationsInOrder) {
    const StageInfo info = Bound().info();
    EXPECT_EQ(info.name, "test.bound");
    ASSERT_EQ(info.params.size(), 5u);
    EXPECT_EQ(info.params[0].name, "count");
    EXPECT_EQ(info.params[2].name, "limit");
    EXPECT_TRUE(info.params[2].is_optional);
    EXPECT_EQ(info.params[4].choices, (std::vector<std::string>{"fast", "exact"}));
}

TEST(ParamBinder, ConfigureFillsTheMembersTypedWithDefaults) {
    Bound s;
    ParamSet p = with_file();
    p.set("mode", std::string("exact"));
    p.set("limit", std::int64_t(4)); // an integer where a number is declared
    s.configure(p);
    EXPECT_EQ(s.count.value, 3);
    EXPECT_FALSE(s.count.given);
    EXPECT_DOUBLE_EQ(s.scale, 0.5);
    ASSERT_TRUE(s.limit);
    EXPECT_DOUBLE_EQ(*s.limit, 4.0);
    EXPECT_EQ(s.file, std::filesystem::path("a.txt"));
    EXPECT_EQ(s.mode, Bound::Mode::Exact);
    EXPECT_EQ(s.checks, 1);
    EXPECT_EQ(s.params().get_int("count"), 3); // stored with the defaults

    // Configured again: what the user gave is marked, an optional left out is reset.
    ParamSet q = with_file();
    q.set("count", std::int64_t(7));
    q.mark_explicit("count");
    s.configure(q);
    EXPECT_EQ(s.count.value, 7);
    EXPECT_TRUE(s.count.given);
    EXPECT_FALSE(s.limit);
    EXPECT_EQ(s.mode, Bound::Mode::Fast);
}

TEST(ParamBinder, ConfigureRefusesWhatTheDeclarationForbids) {
    Bound s;
    EXPECT_EQ(error_of(s, {}), "parameter \"file\" is required: which file");
    ParamSet p = with_file();
    p.set("cuont", std::int64_t(2));
    EXPECT_EQ(error_of(s, p), "unknown parameter \"cuont\" (parameters: count, scale, limit, file, mode)");
    p = with_file();
    p.set("count", std::int64_t(11));
    EXPECT_EQ(error_of(s, p), "count must be in [1, 10], got 11");
    p = with_file();
    p.set("scale", true);
    EXPECT_EQ(error_of(s, p), "scale must be a number, got true");
    p = with_file();
    p.set("mode", std::string("exact"));
    p.set("scale", 1.0);
    EXPECT_EQ(error_of(s, p), "exact needs a scale up to 0.9");
    EXPECT_EQ(s.checks, 1); // check() runs once the members are set, not before
}

TEST(ParamBinder, AMemberOfTheWrongKindIsAStageBug) {
    EXPECT_THROW(Misbound<bool>(ParamSpec::Float("x", 1.0, 0, 2, "", "")).info(), std::logic_error);
    EXPECT_THROW(Misbound<double>(ParamSpec::Float("x", 1.0, 0, 2, "", "").optional()).info(), std::logic_error);
    EXPECT_THROW(Misbound<std::optional<int>>(ParamSpec::Int("x", 1, 0, 2, "", "")).info(), std::logic_error);
    EXPECT_NO_THROW(Misbound<std::string>(ParamSpec::Enum("x", "a", {"a", "b"}, "")).info());
}
