// Two manifests the same, field by field (image paths compared once made absolute and
// normal), with the view's key in the failure message: the round-trip tests of the manifest
// writer and of turnaround sheets.
#pragma once
#include "io/manifest.h"

namespace cm::test {

void expect_same_manifest(const Manifest& a, const Manifest& b);

} // namespace cm::test
