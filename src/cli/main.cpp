// The conceptmesh command: parses the command line and dispatches to a sub-command.
#include <malloc.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <regex>

#include <tbb/global_control.h>
#if defined(CONCEPTMESH_MIMALLOC)
#include <mimalloc.h>
#endif

#include "cli/commands.h"
#include "core/error.h"
#include "core/progress.h"
#include "io/file_commit.h"
#include "io/limits.h"
#include "plugins/registry.h"

namespace cm::cli {

std::string shorten_long_words(const std::string& text) {
    constexpr std::size_t kLongest = 240, kKeep = 100;
    std::string out;
    std::size_t i = 0;
    while (i < text.size()) {
        std::size_t j = i;
        while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
        if (j - i > kLongest)
            out += text.substr(i, kKeep) + "...(" + std::to_string(j - i) + " characters)..." +
                   text.substr(j - kKeep, kKeep);
        else out.append(text, i, j - i);
        for (i = j; i < text.size() && std::isspace(static_cast<unsigned char>(text[i])); ++i)
            out += text[i] == '\n' ? ' ' : text[i]; // one line
    }
    return out;
}

void print_error(const std::string& text) { std::cerr << "conceptmesh: error: " << shorten_long_words(text) << "\n"; }
void print_warning(const std::string& text) {
    std::cerr << "conceptmesh: warning: " << shorten_long_words(text) << "\n";
}

// CLI11 says "Value abc not in range 0 to 4096" for a word where a number belongs, and
// prints the largest double as the bound of a non-negative number: said plainly instead.
std::string plain_parse_error(std::string text) {
    static const std::regex range(R"(^(.*): Value (.*) not in range (\S+) to (\S+)$)");
    std::smatch m;
    if (!std::regex_match(text, m, range)) return text;
    char* end = nullptr;
    const std::string value = m[2];
    std::strtod(value.c_str(), &end);
    const bool number = !value.empty() && end && *end == '\0';
    const double hi = std::strtod(std::string(m[4]).c_str(), nullptr);
    const std::string bounds = hi > 1e300 ? "a number >= " + std::string(m[3])
                                          : "a number in [" + std::string(m[3]) + ", " + std::string(m[4]) + "]";
    return std::string(m[1]) + ": " + (number ? value : "\"" + value + "\" is not a number; ") +
           (number ? " is out of range; give " : "give ") + bounds;
}

void print_plugin_diagnostics(const GlobalOptions& g) {
    // Plugins load on first use: a call after more of them loaded prints what they added.
    static std::size_t printed = 0;
    const auto all = Registry::global().diagnostics();
    if (!g.quiet)
        for (std::size_t i = printed; i < all.size(); ++i) print_warning(all[i]);
    printed = all.size();
}

} // namespace cm::cli

namespace {

// The signal that asked to stop: the exit status is 128 + its number (130 for Ctrl-C,
// 143 for SIGTERM), as shells report it.
volatile std::sig_atomic_t g_signal = SIGINT;

extern "C" void on_sigint(int sig) {
    g_signal = sig;
    // First Ctrl-C: ask every stage to stop at its next check (within a chunk of work);
    // a second one ends the process at once.
    if (cm::cancel_requested().exchange(true)) {
        cm::remove_uncommitted_files_now(); // no unwinding past this point: no file may stay
        _exit(128 + sig);
    }
    static const char msg[] = "\nconceptmesh: stopping (Ctrl-C again to abort at once)\n";
    [[maybe_unused]] auto n = ::write(2, msg, sizeof(msg) - 1);
}

#if defined(CONCEPTMESH_MIMALLOC)
// mimalloc, on transparent huge pages (2 MB: one fault where glibc's 4 kB pages take 512), from
// each thread's first segment on, keeping what it frees for reuse. This must be set before the
// first allocation, which the libraries' initialisers make: the executable's preinit array runs
// before any of them, with the environment as its third argument (libc is not initialised yet,
// so nothing here calls it). Where the environment names an option (MIMALLOC_LARGE_OS_PAGES=0
// for the least memory), it decides. Up to a third more peak memory at high resolutions.
bool names(char** env, const char* option) {
    for (; env && *env; ++env) {
        const char* e = *env;
        const char* o = option;
        while (*o && *e == *o) ++e, ++o;
        if (!*o && *e == '=') return true;
    }
    return false;
}

// Whether mimalloc's blocks of more than 16 MB go on huge pages too (see mmap below): unless the
// environment names MIMALLOC_LARGE_OS_PAGES, which then leaves huge pages to mimalloc alone.
bool huge_mappings = false;

void set_allocator_options(int, char**, char** env) {
    huge_mappings = !names(env, "MIMALLOC_LARGE_OS_PAGES");
    if (huge_mappings) mi_option_set(mi_option_large_os_pages, 1);
    if (!names(env, "MIMALLOC_EAGER_COMMIT_DELAY")) mi_option_set(mi_option_eager_commit_delay, 0);
}

[[gnu::section(".preinit_array"), gnu::used]] void (*const preinit_allocator)(int, char**,
                                                                              char**) = set_allocator_options;
#endif

} // namespace

#if defined(CONCEPTMESH_MIMALLOC) && defined(__linux__) && (defined(__x86_64__) || defined(__aarch64__))
// mimalloc maps each block of more than 16 MB on its own, rounded to 64 kB, and asks for huge
// pages only for mappings that are multiples of 2 MB: those blocks came on 4 kB pages, and for
// some sizes each allocation was mapped afresh (a mesh's faces, an adjacency table: 26 MB at
// resolution 1024), faulted in page by page: 75-80 ms for 26 MB on a machine where a fault
// costs about 12 us, against 2 ms on huge pages (man at 1024: 21 k faults a run, now 1.7 k).
// The executable's mmap is the one mimalloc calls: it is the system call, as libc's is on
// these machines (the kernel checks the arguments), and advises anonymous writable mappings
// of 2 MB or more onto transparent huge pages. Every other caller of mmap in the process gets
// the same advice for such mappings; libc's own (thread stacks) do not come here.
extern "C" void* mmap(void* addr, std::size_t length, int prot, int flags, int fd, off_t offset) {
    const long r = ::syscall(SYS_mmap, addr, length, prot, flags, fd, offset);
    if (r == -1) return MAP_FAILED; // syscall() sets errno
    void* p = reinterpret_cast<void*>(r);
    if (huge_mappings && (flags & MAP_ANONYMOUS) && (prot & PROT_WRITE) && length >= (std::size_t(2) << 20))
        ::madvise(p, length, MADV_HUGEPAGE);
    return p;
}
#endif

int main(int argc, char** argv) {
    // Stages allocate and free images and meshes of megabytes to tens of megabytes one after
    // the other, and each first touch of a fresh 4 kB page costs a fault (on a virtual machine,
    // several microseconds each). docs/results/speed.md has the figures.
#if !defined(CONCEPTMESH_MIMALLOC) // mimalloc's options are set before main: set_allocator_options
    // glibc: freed memory is kept for reuse (by default, heap tops above 128 kB go back to the
    // system and every new buffer is faulted in and zeroed again), and blocks up to 32 MB
    // (glibc's largest mmap threshold; setting any threshold fixes it, so it is set too) come
    // from the heap. About a tenth more peak memory.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);

    CLI::App app{
        "conceptmesh: turns concept art (a few drawn views of one object) into a 3D mesh.\n"
        "Stages are plugins composed as a YAML graph; see `conceptmesh stages`.",
        "conceptmesh"};
    app.set_version_flag("--version", std::string("conceptmesh ") + CONCEPTMESH_VERSION_STRING);
    app.require_subcommand(1);
    // Resource limits, accepted before or after the sub-command (conceptmesh run p.yaml --threads 2).
    app.fallthrough();
    cm::ResourceLimits& limits = cm::resource_limits();
    int threads = 0;
    app.add_option("--threads", threads, "Worker threads (0: one per core)")->check(CLI::Range(0, 4096));
    app.add_option("--max-memory", limits.max_memory,
                   "Refuse work estimated to need more memory than this (e.g. 8G, 512M; 0: no limit; default 80% "
                   "of physical memory)")
        ->transform(CLI::AsSizeValue(true))
        ->default_str(cm::format_bytes(limits.max_memory));
    app.add_option("--max-image-pixels", limits.max_image_pixels,
                   "Refuse images larger than this many pixels, read from the header before decoding (0: no limit)")
        ->capture_default_str();
    app.add_option("--max-views", limits.max_views, "Refuse views manifests with more views than this (0: no limit)")
        ->capture_default_str();
    cm::cli::GlobalOptions g;
    std::function<int()> action;
    cm::cli::add_run_command(app, g, action);
    cm::cli::add_validate_command(app, g, action);
    cm::cli::add_stages_command(app, g, action);
    cm::cli::add_schema_command(app, g, action);
    cm::cli::add_render_views_command(app, g, action);
    cm::cli::add_compare_command(app, g, action);
    cm::cli::add_preview_command(app, g, action);
    cm::cli::add_check_command(app, g, action);
    cm::cli::add_batch_command(app, g, action);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A word that is not a command (`conceptmesh silhouette x.png`): say so, and which are.
        const bool missing = dynamic_cast<const CLI::RequiredError*>(&e) || dynamic_cast<const CLI::ExtrasError*>(&e);
        if (missing && app.get_subcommands().empty()) {
            const std::vector<std::string> rest = app.remaining();
            std::string names;
            for (const CLI::App* sub : app.get_subcommands({})) names += (names.empty() ? "" : ", ") + sub->get_name();
            const bool word = !rest.empty() && !rest.front().empty() && rest.front()[0] != '-';
            cm::cli::print_error((word           ? "unknown command \"" + rest.front() + "\""
                                  : rest.empty() ? std::string("no command")
                                                 : "unknown option \"" + rest.front() + "\" before the command") +
                                 "; the commands are " + names + " (see conceptmesh --help)");
            return 2;
        }
        cm::cli::print_error(cm::cli::plain_parse_error(e.what()) + " (see conceptmesh --help)");
        return 2;
    }
    std::unique_ptr<tbb::global_control> thread_limit;
    if (threads > 0)
        thread_limit =
            std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    try {
        return action ? action() : 2;
    } catch (const cm::Cancelled& e) {
        const char* name = g_signal == SIGTERM ? "SIGTERM" : g_signal == SIGINT ? "SIGINT" : "a signal";
        cm::cli::print_error(std::string(e.what()) + " (" + name + "); no output was written");
        return 128 + int(g_signal);
    } catch (const cm::UsageError& e) {
        cm::cli::print_error(e.what());
        return 2;
    } catch (const std::exception& e) {
        cm::cli::print_error(e.what());
        return 1;
    }
}
