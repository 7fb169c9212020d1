#include "raplas/util/atomic_file.hpp"

#include <dirent.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "raplas/util/error.hpp"

namespace raplas {

namespace {

void split(const std::string& target, std::string& dir, std::string& base) {
    dir.clear();
    base = target;
    const auto slash = target.find_last_of('/');
    if (slash != std::string::npos) {
        dir = target.substr(0, slash + 1);
        base = target.substr(slash + 1);
    }
}

// The process id in a temporary file's name ".BASE.raplas-tmp-PID[.EXT]"
// (or, as older versions named them, ".BASE.tmpPID[.EXT]"); 0 when `name`
// is no temporary file of `base` (any base when `base` is empty).
long temp_owner(const std::string& name, const std::string& base) {
    if (name.size() < 2 || name[0] != '.') return 0;
    for (const char* mark : {".raplas-tmp-", ".tmp"}) {
        std::size_t at;
        if (!base.empty()) {
            if (name.compare(1, base.size(), base) != 0 || name.compare(1 + base.size(), std::strlen(mark), mark) != 0)
                continue;
            at = 1 + base.size();
        } else {
            at = name.rfind(mark);
            if (at == std::string::npos || at < 2) continue;
        }
        const char* digits = name.c_str() + at + std::strlen(mark);
        char* end = nullptr;
        const long pid = std::strtol(digits, &end, 10);
        if (end == digits || pid <= 0 || (*end != '\0' && *end != '.')) continue;
        return pid;
    }
    return 0;
}

}  // namespace

std::string temp_path_for(const std::string& target) {
    std::string dir, base;
    split(target, dir, base);
    remove_stale_temps(dir.empty() ? "." : dir, base);
    std::string ext;
    auto dot = base.find_last_of('.');
    if (dot != std::string::npos && dot > 0) ext = base.substr(dot);
    return dir + "." + base + ".raplas-tmp-" + std::to_string(::getpid()) + ext;
}

std::size_t remove_stale_temps(const std::string& dir, const std::string& base) {
    std::size_t removed = 0;
    DIR* d = ::opendir(dir.c_str());
    if (!d) return 0;
    std::vector<std::string> stale;
    while (const dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        const long pid = temp_owner(n, base);
        if (pid > 0 && pid != long(::getpid()) && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) stale.push_back(n);
    }
    ::closedir(d);
    for (const auto& n : stale) removed += std::remove((dir + "/" + n).c_str()) == 0;
    return removed;
}

void write_atomically(const std::string& target, const std::function<void(const std::string&)>& write) {
    const std::string tmp = temp_path_for(target);
    try {
        write(tmp);
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), target.c_str()) != 0) {
        int err = errno;
        std::remove(tmp.c_str());
        throw InputError(target + ": cannot write: " + std::strerror(err));
    }
}

void write_file_atomically(const std::string& target, const std::string& contents) {
    write_atomically(target, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError(target + ": cannot write: " + std::strerror(errno));
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.close();
        if (!out) throw InputError(target + ": write failed");
    });
}

}  // namespace raplas
