// A zip archive of stored (uncompressed) files whose data start on 64-byte boundaries: the
// package format of USDZ, which a reader maps into memory and reads in place, so it allows
// neither compression nor unaligned data.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/progress.h"

namespace cm {

/// One file of the archive: its name in the archive and its bytes (which must outlive the call).
struct ZipEntry {
    std::string name;
    std::string_view data;
};

/// Writes `entries`, in their order, as a zip archive to `file`: each stored (method 0, no
/// data descriptor), with its CRC-32 and sizes in its local header, its data at an offset that
/// is a multiple of 64 (padded by an extra field of the local header, as Pixar's usdzip does),
/// no timestamps (1980-01-01 00:00, so equal contents give equal bytes), then the central
/// directory. Names in UTF-8. `progress` reports per chunk; a stop it throws leaves a partial
/// file. @throw cm::Error naming the file when it cannot be written or an entry exceeds zip's
/// 4 GiB (no Zip64).
void write_zip_store(const std::filesystem::path& file, const std::vector<ZipEntry>& entries, Progress progress = {});

} // namespace cm
