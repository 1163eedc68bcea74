#include "support/manifest_checks.h"

#include <gtest/gtest.h>

namespace cm::test {
namespace {

std::filesystem::path normal(const std::filesystem::path& p) { return std::filesystem::absolute(p).lexically_normal(); }

} // namespace

void expect_same_manifest(const Manifest& a, const Manifest& b) {
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.bounds, b.bounds);
    ASSERT_EQ(a.views.size(), b.views.size());
    for (std::size_t i = 0; i < a.views.size(); ++i) {
        const ManifestView &x = a.views[i], &y = b.views[i];
        SCOPED_TRACE(x.key);
        EXPECT_EQ(x.key, y.key);
        EXPECT_EQ(normal(x.image), normal(y.image));
        EXPECT_EQ(x.view, y.view);
        EXPECT_EQ(x.azimuth, y.azimuth);
        EXPECT_EQ(x.elevation, y.elevation);
        EXPECT_EQ(x.matrix, y.matrix);
        EXPECT_EQ(x.scale, y.scale);
        EXPECT_EQ(x.origin, y.origin);
        EXPECT_EQ(x.background, y.background);
        EXPECT_EQ(x.threshold, y.threshold);
        EXPECT_EQ(x.keep, y.keep);
        EXPECT_EQ(x.holes, y.holes);
        EXPECT_EQ(x.close_gaps, y.close_gaps);
        EXPECT_EQ(x.mask.empty(), y.mask.empty());
        if (!x.mask.empty() && !y.mask.empty()) {
            EXPECT_EQ(normal(x.mask), normal(y.mask));
        }
        EXPECT_EQ(x.shadow, y.shadow);
        EXPECT_EQ(x.photo, y.photo);
    }
    ASSERT_EQ(a.sheets.size(), b.sheets.size());
    for (std::size_t i = 0; i < a.sheets.size(); ++i) {
        EXPECT_EQ(normal(a.sheets[i].image), normal(b.sheets[i].image));
        EXPECT_EQ(a.sheets[i].views, b.sheets[i].views);
    }
}

} // namespace cm::test
