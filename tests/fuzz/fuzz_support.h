// Shared by the fuzz targets: the input bytes as a file, since the readers take paths.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace cm::fuzz {

/// Writes `data` to a file of this process named `name` (in the temporary folder) and
/// returns its path; the same path each call, so the folder does not fill up.
std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, const char* name);

} // namespace cm::fuzz
