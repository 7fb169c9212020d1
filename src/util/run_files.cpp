#include "raplas/util/run_files.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "raplas/util/error.hpp"

namespace raplas {

namespace fs = std::filesystem;

namespace {

std::string resolved(const std::string& p) {
    std::error_code ec;
    fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
    return ec ? fs::absolute(p).lexically_normal().string() : r.string();
}

// "--json out.json" or "out.json" when the option is the path itself.
std::string named(const std::string& option, const std::string& path) {
    return option.empty() ? path : option + " " + path;
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    struct stat sa{}, sb{};
    const bool ea = ::stat(a.c_str(), &sa) == 0, eb = ::stat(b.c_str(), &sb) == 0;
    if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea != eb) return false;
    return resolved(a) == resolved(b);
}

void RunFiles::input(const std::string& option, const std::string& path) {
    if (!path.empty()) inputs_.push_back({option, path});
}

void RunFiles::output(const std::string& option, const std::string& path) {
    if (!path.empty()) outputs_.push_back({option, path});
}

void RunFiles::check() const {
    for (std::size_t i = 0; i < outputs_.size(); ++i) {
        const Entry& o = outputs_[i];
        std::error_code ec;
        if (fs::is_directory(o.path, ec)) throw InputError(named(o.option, o.path) + ": is a directory");
        const fs::path parent = fs::absolute(o.path, ec).parent_path();
        if (!fs::is_directory(parent, ec))
            throw InputError(named(o.option, o.path) + ": directory " + parent.lexically_normal().string() +
                             " does not exist");
        if (::access(parent.c_str(), W_OK) != 0)
            throw InputError(named(o.option, o.path) + ": directory " + parent.lexically_normal().string() +
                             " is not writable");
        for (const Entry& in : inputs_)
            if (same_file(o.path, in.path))
                throw InputError(named(o.option, o.path) + ": is the input " + named(in.option, in.path) +
                                 "; a run never writes over a file it reads: choose another output");
        for (std::size_t j = 0; j < i; ++j)
            if (same_file(o.path, outputs_[j].path))
                throw InputError(named(o.option, o.path) + ": is also the output " +
                                 named(outputs_[j].option, outputs_[j].path) + "; give each output its own file");
    }
}

}  // namespace raplas
