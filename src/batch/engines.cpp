// Local processes (fork/exec of each task script, wait4 for its peak memory) and Slurm
// (sbatch --array, squeue) for conceptmesh batch.
#include "batch/engines.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "io/file_commit.h"

namespace fs = std::filesystem;

namespace cm::batch {

namespace {

std::string bar(std::size_t done, std::size_t total, int width = 30) {
    const int fill = total ? int(double(done) / double(total) * width + 0.5) : width;
    return "[" + std::string(std::size_t(fill), '#') + std::string(std::size_t(width - fill), ' ') + "]";
}

bool status_recorded(const AssetPlan& p) { return fs::exists(p.dir / "exit-status"); }

int recorded_rc(const AssetPlan& p) {
    FILE* f = std::fopen((p.dir / "exit-status").c_str(), "r");
    int rc = -1;
    if (f) {
        if (std::fscanf(f, "%d", &rc) != 1) rc = -1;
        std::fclose(f);
    }
    return rc;
}

} // namespace

std::map<std::string, double> run_local(const std::vector<const AssetPlan*>& plans, int jobs, bool quiet) {
    const bool tty = ::isatty(2) != 0 && !quiet;
    std::map<pid_t, const AssetPlan*> running;
    std::map<std::string, double> peak;
    std::size_t next = 0, done = 0, failed = 0;
    const auto t0 = std::chrono::steady_clock::now();
    auto draw = [&] {
        if (!tty) return;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        char tail[128];
        std::snprintf(tail, sizeof tail, " %zu/%zu assets, %zu failed, %zu running, %.0f s", done, plans.size(), failed,
                      running.size(), s);
        std::fputs(("\r\033[K" + bar(done, plans.size()) + tail).c_str(), stderr);
        std::fflush(stderr);
    };
    bool stopping = false;
    while (done < plans.size() && !(stopping && running.empty())) {
        if (cancel_requested() && !stopping) {
            stopping = true;
            // Each task is a process group of its own (its shell and the run): stop the run, not
            // only the shell waiting for it.
            for (const auto& [pid, p] : running) ::kill(-pid, SIGTERM);
        }
        while (!stopping && running.size() < std::size_t(jobs) && next < plans.size()) {
            const AssetPlan* p = plans[next++];
            const std::string script = (p->dir / "task.sh").string();
            const pid_t pid = ::fork();
            if (pid < 0) throw Error(std::string("cannot start a process for asset \"") + p->spec->name + "\"");
            if (pid == 0) {
                ::setpgid(0, 0);
                const int devnull = ::open("/dev/null", O_RDONLY);
                if (devnull >= 0) ::dup2(devnull, 0);
                ::execl("/bin/sh", "sh", script.c_str(), static_cast<char*>(nullptr));
                _exit(127);
            }
            ::setpgid(pid, pid); // also here, so that a stop right after the fork finds the group
            running[pid] = p;
        }
        draw();
        int status = 0;
        struct rusage ru {};
        const pid_t pid = ::wait4(-1, &status, WNOHANG, &ru);
        if (pid <= 0) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            continue;
        }
        auto it = running.find(pid);
        if (it == running.end()) continue;
        const AssetPlan* p = it->second;
        running.erase(it);
        ++done;
        peak[p->spec->name] = double(ru.ru_maxrss) / 1024.0; // KiB on Linux
        const int rc = recorded_rc(*p);
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && rc == 0;
        failed += !ok;
        if (!quiet) {
            if (tty) std::fputs("\r\033[K", stderr);
            std::cerr << "conceptmesh: " << p->spec->name << ": "
                      << (ok         ? "done"
                          : stopping ? "stopped"
                                     : "FAILED")
                      << " (" << done << "/" << plans.size() << ")\n";
        }
    }
    if (tty) std::fputs("\r\033[K", stderr);
    if (stopping) throw Cancelled();
    return peak;
}

int run_capture(const std::vector<std::string>& argv, std::string& out, std::string& err) {
    int po[2], pe[2];
    if (::pipe(po) != 0 || ::pipe(pe) != 0) throw Error("cannot create a pipe to run " + argv.at(0));
    const pid_t pid = ::fork();
    if (pid < 0) throw Error("cannot start " + argv.at(0));
    if (pid == 0) {
        ::dup2(po[1], 1);
        ::dup2(pe[1], 2);
        ::close(po[0]);
        ::close(pe[0]);
        std::vector<char*> a;
        for (const auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
        a.push_back(nullptr);
        ::execvp(a[0], a.data());
        std::fprintf(stderr, "cannot run %s: not found\n", a[0]);
        _exit(127);
    }
    ::close(po[1]);
    ::close(pe[1]);
    // Read both pipes in turn so that neither fills up and blocks the child.
    std::string* bufs[2] = {&out, &err};
    int fds[2] = {po[0], pe[0]};
    int open = 2;
    while (open > 0) {
        fd_set set;
        FD_ZERO(&set);
        int maxfd = -1;
        for (int fd : fds)
            if (fd >= 0) {
                FD_SET(fd, &set);
                maxfd = std::max(maxfd, fd);
            }
        if (::select(maxfd + 1, &set, nullptr, nullptr, nullptr) < 0) continue;
        for (int i = 0; i < 2; ++i) {
            if (fds[i] < 0 || !FD_ISSET(fds[i], &set)) continue;
            char buf[4096];
            const ssize_t n = ::read(fds[i], buf, sizeof buf);
            if (n > 0) {
                bufs[i]->append(buf, std::size_t(n));
            } else {
                ::close(fds[i]);
                fds[i] = -1;
                --open;
            }
        }
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string submit_slurm(const std::vector<const AssetPlan*>& plans, const SlurmOptions& o, const fs::path& out_dir,
                         const std::string& batch_name) {
    const fs::path meta = fs::absolute(out_dir) / ".batch";
    fs::create_directories(meta);
    std::string list;
    double mem = o.mem_mib;
    for (const auto* p : plans) {
        list += (p->dir / "task.sh").string() + "\n";
        if (o.mem_mib <= 0) mem = std::max(mem, p->memory_mib);
    }
    write_file_atomic(meta / "tasks.list", list);
    // Task i of the array runs line i+1 of the list: the asset's own script, which keeps its log.
    write_file_atomic(meta / "array.sh",
                      "#!/bin/sh\n"
                      "# Written by conceptmesh batch: task N of the array runs line N+1 of tasks.list.\n"
                      "task=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" '" +
                          (meta / "tasks.list").string() +
                          "')\n"
                          "[ -n \"$task\" ] || { echo \"no task $SLURM_ARRAY_TASK_ID in tasks.list\" >&2; exit 1; }\n"
                          "exec sh \"$task\"\n");
    std::vector<std::string> argv = {"sbatch",
                                     "--parsable",
                                     "--job-name=conceptmesh-" + batch_name,
                                     "--output=" + (meta / "slurm-%A_%a.out").string(),
                                     "--chdir=" + meta.string(),
                                     "--mem=" + std::to_string(long(std::ceil(mem))) + "M"};
    std::string array = "--array=0-" + std::to_string(plans.size() - 1);
    if (o.jobs > 0) array += "%" + std::to_string(o.jobs);
    argv.push_back(array);
    if (!o.partition.empty()) argv.push_back("--partition=" + o.partition);
    if (!o.time_limit.empty()) argv.push_back("--time=" + o.time_limit);
    std::istringstream extra(o.extra);
    for (std::string w; extra >> w;) argv.push_back(w);
    argv.push_back((meta / "array.sh").string());
    std::string out, err;
    const int rc = run_capture(argv, out, err);
    if (rc != 0) {
        // sbatch says it in a few lines ("sbatch: error: ..."): one line here.
        std::string why;
        std::istringstream lines(err);
        for (std::string l; std::getline(lines, l);) {
            if (l.rfind("sbatch: error: ", 0) == 0) l = l.substr(15);
            if (!l.empty()) why += (why.empty() ? "" : "; ") + l;
        }
        throw Error("sbatch refused the batch (exit " + std::to_string(rc) + "): " + why);
    }
    const std::string id = out.substr(0, out.find_first_of(";\n"));
    if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
        throw Error("sbatch gave no job id (it printed \"" + out + "\")");
    write_file_atomic(meta / "sbatch.txt", [&] {
        std::string cmd;
        for (const auto& a : argv) cmd += (cmd.empty() ? "" : " ") + a;
        return cmd + "\n" + id + "\n";
    }());
    return id;
}

int slurm_tasks_left(const std::string& job_id) {
    std::string out, err;
    const int rc = run_capture({"squeue", "--noheader", "--array", "--jobs=" + job_id, "--format=%i %T"}, out, err);
    if (rc != 0) {
        // A job that has left the controller's memory is no longer known: nothing is left.
        if (err.find("Invalid job id") != std::string::npos) return 0;
        return -1;
    }
    int n = 0;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) n += !line.empty();
    return n;
}

void wait_slurm(const std::string& job_id, const std::vector<const AssetPlan*>& plans, bool quiet) {
    const bool tty = ::isatty(2) != 0 && !quiet;
    std::size_t last_done = std::size_t(-1);
    int unknown = 0;
    while (true) {
        if (cancel_requested()) {
            std::string out, err;
            run_capture({"scancel", job_id}, out, err);
            throw Cancelled();
        }
        const int left = slurm_tasks_left(job_id);
        std::size_t done = 0, failed = 0;
        for (const auto* p : plans)
            if (status_recorded(*p)) {
                ++done;
                failed += recorded_rc(*p) != 0;
            }
        if (!quiet && (tty || done != last_done)) {
            char line[160];
            std::snprintf(line, sizeof line, "slurm job %s: %zu/%zu assets done, %zu failed, %d queued or running",
                          job_id.c_str(), done, plans.size(), failed, std::max(left, 0));
            if (tty) std::fputs(("\r\033[K" + bar(done, plans.size()) + " " + line).c_str(), stderr);
            else std::cerr << "conceptmesh: " << line << "\n";
            std::fflush(stderr);
            last_done = done;
        }
        if (left == 0) break;
        if (left < 0 && ++unknown > 30) throw Error("squeue cannot say how job " + job_id + " is doing");
        std::this_thread::sleep_for(std::chrono::seconds(1));
    }
    if (tty) std::fputs("\r\033[K", stderr);
}

} // namespace cm::batch
