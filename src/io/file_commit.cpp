#include "io/file_commit.h"

#include <unistd.h>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// Every uncommitted temporary file and made folder of the process, where a signal handler
// can read them without locking: fixed slots of C strings, each "f<path>" (a file) or
// "d<path>" (a folder). A slot's string is never freed (a handler may be reading it); a
// run stages a handful of files, so this stays small.
constexpr std::size_t kPendingSlots = 4096;
std::atomic<const char*> g_pending[kPendingSlots];

void note_pending(const fs::path& p, bool folder) {
    const std::string tagged = (folder ? "d" : "f") + p.string();
    const char* copy = ::strdup(tagged.c_str());
    if (!copy) return;
    for (auto& slot : g_pending) {
        const char* expected = nullptr;
        if (slot.compare_exchange_strong(expected, copy)) return;
    }
}

// A forgotten slot's string is kept here, not freed: a signal handler may still be reading it.
// (Kept reachable, so a leak checker sees a pool, not a leak.)
std::mutex g_retired_mutex;
std::vector<const char*> g_retired;

void forget_pending(const fs::path& p) {
    for (auto& slot : g_pending) {
        const char* s = slot.load();
        if (s && p == s + 1 && slot.compare_exchange_strong(s, nullptr)) {
            const std::lock_guard<std::mutex> lock(g_retired_mutex);
            g_retired.push_back(s);
            return;
        }
    }
}

} // namespace

void remove_uncommitted_files_now() noexcept {
    for (auto& slot : g_pending)
        if (const char* s = slot.load(); s && s[0] == 'f') ::unlink(s + 1);
    for (std::size_t i = kPendingSlots; i-- > 0;) // folders last, innermost (latest) first
        if (const char* s = g_pending[i].load(); s && s[0] == 'd') ::rmdir(s + 1);
}

FileCommit::~FileCommit() {
    if (!done_) discard();
}

void FileCommit::add(const fs::path& tmp, const fs::path& final_path) {
    std::lock_guard<std::mutex> lock(mutex_);
    staged_.emplace_back(tmp, final_path);
    note_pending(tmp, false);
    // The missing folders on the way, outermost first, so a failed run can take them back.
    std::vector<fs::path> missing;
    std::error_code ec;
    for (fs::path d = fs::absolute(final_path, ec).parent_path(); !d.empty() && !fs::exists(d, ec);
         d = d.parent_path()) {
        missing.push_back(d);
        if (d == d.root_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        if (!fs::create_directory(*it, ec) && ec)
            throw Error("cannot make the folder \"" + it->string() + "\" for \"" + final_path.string() +
                        "\": " + ec.message());
        made_dirs_.push_back(*it);
        note_pending(*it, true);
    }
}

fs::path FileCommit::stage(const fs::path& final_path) {
    fs::path tmp = temporary_path(final_path);
    add(tmp, final_path);
    return tmp;
}

std::vector<fs::path> FileCommit::finals() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<fs::path> out;
    for (const auto& s : staged_) out.push_back(s.second);
    return out;
}

std::string FileCommit::with_final_names(std::string text) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto replace_all = [&text](const std::string& from, const std::string& to) {
        if (from.empty()) return;
        for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
            text.replace(at, from.size(), to);
    };
    for (const auto& [tmp, fin] : staged_) {
        replace_all(tmp.string(), fin.string());
        replace_all(tmp.filename().string(), fin.filename().string());
    }
    return text;
}

std::vector<fs::path> FileCommit::commit() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::error_code ec;
    for (const auto& [tmp, fin] : staged_)
        if (fs::is_directory(fin, ec)) {
            const std::string message = "cannot write \"" + fin.string() + "\": it is a folder";
            discard_locked(); // clears staged_, which fin refers into
            throw Error(message);
        }
    // Each file that is replaced is first moved aside, so a failure can put it back.
    std::vector<std::pair<fs::path, fs::path>> moved; // final -> the file it replaced ("" if none)
    for (const auto& [tmp, fin] : staged_) {
        fs::path aside;
        if (fs::exists(fin, ec)) {
            aside = temporary_path(fin);
            fs::rename(fin, aside, ec);
        }
        if (!ec) fs::rename(tmp, fin, ec);
        if (ec) {
            const std::string why = ec.message(); // before the clean-up changes it
            if (!aside.empty() && !fs::exists(fin)) fs::rename(aside, fin, ec);
            for (auto it = moved.rbegin(); it != moved.rend(); ++it) {
                fs::remove(it->first, ec);
                if (!it->second.empty()) fs::rename(it->second, it->first, ec);
            }
            const std::string message = "could not move the finished file to \"" + fin.string() + "\": " + why;
            discard_locked(); // clears staged_, which fin refers into
            throw Error(message);
        }
        moved.emplace_back(fin, aside);
    }
    for (const auto& m : moved)
        if (!m.second.empty()) fs::remove(m.second, ec);
    for (const auto& [tmp, fin] : staged_) forget_pending(tmp);
    for (const auto& d : made_dirs_) forget_pending(d);
    done_ = true;
    std::vector<fs::path> out;
    for (const auto& m : moved) out.push_back(m.first);
    return out;
}

void FileCommit::discard() {
    std::lock_guard<std::mutex> lock(mutex_);
    discard_locked();
}

void FileCommit::discard_locked() {
    std::error_code ec;
    for (const auto& [tmp, fin] : staged_) {
        fs::remove(tmp, ec);
        forget_pending(tmp);
    }
    for (const auto& d : made_dirs_) forget_pending(d);
    // Innermost first; a folder something else has put files into stays.
    for (auto it = made_dirs_.rbegin(); it != made_dirs_.rend(); ++it)
        if (fs::is_empty(*it, ec)) fs::remove(*it, ec);
    staged_.clear();
    made_dirs_.clear();
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
