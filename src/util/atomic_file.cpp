#include "raplas/util/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "raplas/util/error.hpp"

namespace raplas {

std::string temp_path_for(const std::string& target) {
    std::string dir, base = target;
    auto slash = target.find_last_of('/');
    if (slash != std::string::npos) {
        dir = target.substr(0, slash + 1);
        base = target.substr(slash + 1);
    }
    std::string ext;
    auto dot = base.find_last_of('.');
    if (dot != std::string::npos && dot > 0) ext = base.substr(dot);
    return dir + "." + base + ".tmp" + std::to_string(::getpid()) + ext;
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
