#include "raplas/util/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "raplas/util/error.hpp"
#include "raplas/util/memory_budget.hpp"

namespace raplas {

namespace {

struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::string read_text_input(const std::string& path, const TextInput& kind) {
    const std::string named = kind.article + " " + kind.noun;
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        throw InputError(path + ": is a directory, not " + named);
    const Fd in{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
    if (in.fd < 0) throw InputError(path + ": cannot open " + kind.noun + ": " + std::strerror(errno));
    auto check = [&](double bytes) {
        check_memory("loading " + path, {{kind.memory_item, kind.memory_factor * bytes}});
    };
    // A regular file's size is known (a /proc file says 0 and is read as a stream).
    std::string text;
    std::size_t next_check = std::size_t(64) << 20;
    if (::fstat(in.fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        check(double(st.st_size));
        text.reserve(std::size_t(st.st_size));
        while (next_check <= std::size_t(st.st_size)) next_check *= 2;
    }
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(in.fd, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw InputError(path + ": cannot read " + kind.noun + ": " + std::strerror(errno));
        }
        if (n == 0) break;
        if (kind.text && std::memchr(buf, '\0', std::size_t(n)))
            throw InputError(path + ": not a text " + kind.noun + " (contains NUL bytes)");
        text.append(buf, std::size_t(n));
        if (text.size() >= next_check) {
            check(double(text.size()));
            next_check *= 2;
        }
    }
    return text;
}

}  // namespace raplas
