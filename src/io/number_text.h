// Numbers as text for the writers of text formats (OBJ, USDA).
#pragma once
#include <charconv>
#include <cstddef>
#include <string>

namespace cm {

/// Appends the shortest decimal text that reads back as exactly `x` (std::to_chars): a file
/// read back holds the very floats written, so a sliver face stays a face. Fixed notation
/// with nine decimals (OpenMesh's) keeps only a few digits of small coordinates: vertices
/// near an axis plane were read back onto one line, and a face of theirs as degenerate.
inline void append_float(std::string& o, float x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    o.append(buf, r.ptr);
}

/// Appends `i` in decimal.
inline void append_index(std::string& o, std::size_t i) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, i);
    o.append(buf, r.ptr);
}

} // namespace cm
