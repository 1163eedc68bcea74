// Views manifests for the calibrated photo sets of ../shared/data/multiview, written
// at run time (the images stay where they are; the manifest names them by path).
#pragma once
#include <filesystem>

namespace cm::test {

/// TUM bunny: 18 binary silhouettes (object black on white) with a 3x4 matrix each.
/// Writes `manifest` referring to the PGM files in `data_dir` (absolute paths).
void write_tum_bunny_manifest(const std::filesystem::path& data_dir, const std::filesystem::path& manifest);

/// Middlebury dinoSparseRing: 16 photos (white plaster on black) with K, R, t; the view
/// the data set's authors left out (dinoSR0006, bad silhouette) is left out here too.
void write_dino_manifest(const std::filesystem::path& data_dir, const std::filesystem::path& manifest);

} // namespace cm::test
