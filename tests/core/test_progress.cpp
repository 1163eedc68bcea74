// cm::Progress, the progress and cancel object of the algorithm contract: where its fractions
// go, how part() maps them, and that a stop asked for reaches every kind of look.
#include <atomic>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/progress.h"

namespace cm {
namespace {

// Records what a node reports, as the command's progress lines would.
class Lines : public ProgressSink {
public:
    void started(const std::string&, const std::string&) override {}
    void progress(const std::string&, double percent, const std::string& what) override {
        percents.push_back(percent);
        whats.push_back(what);
    }
    void finished(const std::string&, double) override {}
    void message(const std::string&, const std::string&, const std::string&) override {}
    std::vector<double> percents;
    std::vector<std::string> whats;
};

TEST(Progress, ADefaultOneReportsNowhereAndNeverStops) {
    const Progress p;
    EXPECT_FALSE(p);
    EXPECT_NO_THROW(p(0.5));
    EXPECT_NO_THROW(p.check());
    EXPECT_NO_THROW(p.part(0.2, 0.4)(1.0));
}

TEST(Progress, PartsMapTheirFractionsIntoTheirRangeClamped) {
    std::vector<double> seen;
    const Progress p([&](double f) { seen.push_back(f); });
    ASSERT_TRUE(p);
    p(0.5);
    p.part(0.2, 0.6)(0.5);                // half of [0.2, 0.6]
    p.part(0.5, 1.0).part(0.0, 0.5)(1.0); // the end of the first half of the second half
    p.part(0.2, 0.4)(7.0);                // past the end: the part's end
    p.part(0.2, 0.4)(-1.0);               // before the start: the part's start
    ASSERT_EQ(seen.size(), 5u);
    EXPECT_DOUBLE_EQ(seen[0], 0.5);
    EXPECT_DOUBLE_EQ(seen[1], 0.4);
    EXPECT_DOUBLE_EQ(seen[2], 0.75);
    EXPECT_DOUBLE_EQ(seen[3], 0.4);
    EXPECT_DOUBLE_EQ(seen[4], 0.2);
}

TEST(Progress, ACheckAloneIsCalledOnEveryLookAndItsThrowStops) {
    int looks = 0;
    bool stop = false;
    const Progress p([&] {
        ++looks;
        if (stop) throw Cancelled();
    });
    p(0.3);
    p.check();
    EXPECT_EQ(looks, 2);
    stop = true;
    EXPECT_THROW(p(0.4), Cancelled);
    EXPECT_THROW(p.part(0.5, 1).check(), Cancelled);
}

TEST(Progress, AReportWithACheckSendsFractionsToOneAndLooksToTheOther) {
    std::vector<double> seen;
    int looks = 0;
    const Progress p([&](double f) { seen.push_back(f); }, [&] { ++looks; });
    p(0.25);
    p.check();
    p.part(0.5, 1.0).check();
    EXPECT_EQ(seen, std::vector<double>{0.25});
    EXPECT_EQ(looks, 2);
}

TEST(Progress, OnAnInterrupterItReportsPercentsWithItsWhatAndStopsWhenAsked) {
    Lines lines;
    std::atomic<bool> stop{false};
    Interrupter node("surface", &lines, &stop);
    const Progress p(node, "marching cubes");
    p.part(0.5, 1.0)(0.5);
    ASSERT_FALSE(lines.percents.empty());
    EXPECT_DOUBLE_EQ(lines.percents.back(), 75.0);
    EXPECT_EQ(lines.whats.back(), "marching cubes");
    EXPECT_NO_THROW(p.check());
    stop = true;
    EXPECT_THROW(p.check(), Cancelled);
    EXPECT_THROW(p(0.9), Cancelled);
}

} // namespace
} // namespace cm
