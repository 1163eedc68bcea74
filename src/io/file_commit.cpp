#include "io/file_commit.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace fs = std::filesystem;

namespace cm {

FileCommit::~FileCommit() {
    if (!done_) discard();
}

void FileCommit::add(const fs::path& tmp, const fs::path& final_path) {
    std::lock_guard<std::mutex> lock(mutex_);
    staged_.emplace_back(tmp, final_path);
}

fs::path FileCommit::stage(const fs::path& final_path) {
    fs::path tmp = temporary_path(final_path);
    add(tmp, final_path);
    return tmp;
}

std::vector<fs::path> FileCommit::commit() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<fs::path> out;
    for (std::size_t i = 0; i < staged_.size(); ++i) {
        const auto& [tmp, fin] = staged_[i];
        std::error_code ec;
        fs::rename(tmp, fin, ec);
        if (ec) {
            for (std::size_t j = i; j < staged_.size(); ++j) fs::remove(staged_[j].first, ec);
            done_ = true;
            throw Error("could not move the finished file to \"" + fin.string() + "\": " + ec.message());
        }
        out.push_back(fin);
    }
    done_ = true;
    return out;
}

void FileCommit::discard() {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [tmp, fin] : staged_) {
        std::error_code ec;
        fs::remove(tmp, ec);
    }
    staged_.clear();
    done_ = true;
}

void write_file_atomic(const fs::path& path, const std::string& bytes) {
    FileCommit files;
    const fs::path tmp = files.stage(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw Error("cannot write \"" + path.string() + "\": " + std::strerror(errno));
        out << bytes;
        if (!out.flush()) throw Error("cannot write \"" + path.string() + "\": " + std::strerror(errno));
    }
    files.commit();
}

} // namespace cm
