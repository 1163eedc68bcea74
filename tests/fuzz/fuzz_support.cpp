#include "fuzz_support.h"

#include <unistd.h>
#include <fstream>
#include <string>

namespace cm::fuzz {

std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, const char* name) {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::temp_directory_path() / ("conceptmesh-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    const auto file = dir / name;
    std::ofstream(file, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return file;
}

} // namespace cm::fuzz
