#include "io/zip_store.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <limits>

#include <zlib.h>

#include "core/error.h"
#include "io/progress_stream.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

constexpr std::uint64_t kAlign = 64;                        // USDZ: every file's data on a 64-byte boundary
constexpr std::uint16_t kPaddingField = 0x1986;             // the extra field's id, as Pixar's usdzip writes it
constexpr std::uint16_t kVersion = 10;                      // 1.0: stored files, no folders
constexpr std::uint16_t kDosDate = (0 << 9) | (1 << 5) | 1; // 1980-01-01, zip's first day
constexpr std::uint16_t kUtf8Names = 1 << 11;

void put16(std::string& o, std::uint64_t v) {
    for (int k = 0; k < 2; ++k) o += char((v >> (8 * k)) & 0xff);
}
void put32(std::string& o, std::uint64_t v) {
    for (int k = 0; k < 4; ++k) o += char((v >> (8 * k)) & 0xff);
}

// What the central directory repeats of a local header.
struct Written {
    std::uint32_t crc = 0;
    std::uint64_t size = 0, offset = 0;
    std::uint16_t flags = 0;
};

std::uint16_t name_flags(const std::string& name) {
    for (unsigned char c : name)
        if (c >= 0x80) return kUtf8Names;
    return 0;
}

// The fields local and central headers share, from "version needed" to the name's length.
void common_fields(std::string& o, const std::string& name, const Written& w) {
    put16(o, kVersion);
    put16(o, w.flags);
    put16(o, 0); // stored
    put16(o, 0); // 00:00
    put16(o, kDosDate);
    put32(o, w.crc);
    put32(o, w.size); // compressed: stored as it is
    put32(o, w.size);
    put16(o, name.size());
}

// The local header of an entry whose header starts at `w.offset`, padded so its data start
// on a 64-byte boundary: an extra field of at least its own 4 bytes when padding is needed.
std::string local_header(const std::string& name, const Written& w) {
    const std::uint64_t end = w.offset + 30 + name.size();
    std::uint64_t extra = 0;
    if (end % kAlign) extra = 4 + (kAlign - (end + 4) % kAlign) % kAlign;
    std::string h;
    put32(h, 0x04034b50);
    common_fields(h, name, w);
    put16(h, extra);
    h += name;
    if (extra) {
        put16(h, kPaddingField);
        put16(h, extra - 4);
        h.append(extra - 4, '\0');
    }
    return h;
}

std::string central_directory(const std::vector<ZipEntry>& entries, const std::vector<Written>& written,
                              std::uint64_t offset) {
    std::string d;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        put32(d, 0x02014b50);
        put16(d, kVersion); // made by: MS-DOS attributes, zip 1.0
        common_fields(d, entries[i].name, written[i]);
        put16(d, 0); // extra
        put16(d, 0); // comment
        put16(d, 0); // disk
        put16(d, 0); // internal attributes
        put32(d, 0); // external attributes
        put32(d, written[i].offset);
        d += entries[i].name;
    }
    const std::uint64_t size = d.size();
    put32(d, 0x06054b50);
    put16(d, 0); // this disk
    put16(d, 0); // the directory's disk
    put16(d, entries.size());
    put16(d, entries.size());
    put32(d, size);
    put32(d, offset);
    put16(d, 0); // comment
    return d;
}

} // namespace

void write_zip_store(const fs::path& file, const std::vector<ZipEntry>& entries, Progress progress) {
    const auto fail = [&](const std::string& why) { throw Error("cannot write \"" + file.string() + "\": " + why); };
    std::uint64_t expected = 22;
    for (const auto& e : entries) {
        expected += 30 + 46 + 2 * e.name.size() + kAlign + e.data.size();
        if (e.data.size() >= std::numeric_limits<std::uint32_t>::max() || e.name.size() > 0xffff)
            fail("\"" + e.name + "\" is too large for a zip archive without Zip64");
    }
    if (entries.size() > 0xffff || expected >= std::numeric_limits<std::uint32_t>::max())
        fail("too large for a zip archive without Zip64");
    ProgressFileStream out(file, expected, std::move(progress));
    if (!out.is_open()) fail(std::strerror(errno));
    std::vector<Written> written(entries.size());
    std::uint64_t offset = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const ZipEntry& e = entries[i];
        Written& w = written[i];
        w.crc = std::uint32_t(
            crc32(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(e.data.data()), uInt(e.data.size())));
        w.size = e.data.size();
        w.offset = offset;
        w.flags = name_flags(e.name);
        const std::string header = local_header(e.name, w);
        out.write(header.data(), std::streamsize(header.size()));
        out.write(e.data.data(), std::streamsize(e.data.size()));
        offset += header.size() + e.data.size();
    }
    const std::string directory = central_directory(entries, written, offset);
    out.write(directory.data(), std::streamsize(directory.size()));
    if (!out.finish()) fail(std::strerror(errno));
}

} // namespace cm
