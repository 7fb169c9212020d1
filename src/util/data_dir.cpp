#include "raplas/util/data_dir.hpp"

#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>

#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/nearest.hpp"

// The data folder relative to the installed executable's folder (GNUInstallDirs:
// bin -> share/raplas) and the source tree, both set by CMakeLists.txt.
#ifndef RAPLAS_DATA_FROM_BIN
#define RAPLAS_DATA_FROM_BIN "../share/raplas"
#endif
#ifndef RAPLAS_SOURCE_DIR
#define RAPLAS_SOURCE_DIR "."
#endif

namespace raplas {

namespace {

bool is_dir(const std::string& path) {
    struct stat st{};
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool exists(const std::string& path) {
    struct stat st{};
    return ::stat(path.c_str(), &st) == 0;
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::vector<std::string> search_dirs(const std::string& folder) {
    std::vector<std::string> dirs{folder};
    for (const auto& d : data_dirs()) dirs.push_back(d + "/" + folder);
    return dirs;
}

}  // namespace

std::vector<std::string> data_dirs() {
    std::vector<std::string> dirs;
    const std::string exe_dir = executable_dir();
    if (!exe_dir.empty()) {
        const std::string installed = exe_dir + RAPLAS_DATA_FROM_BIN;
        if (is_dir(installed)) dirs.push_back(absolute_path(installed));
    }
    const std::string source = RAPLAS_SOURCE_DIR;
    if (is_dir(source) && std::find(dirs.begin(), dirs.end(), absolute_path(source)) == dirs.end())
        dirs.push_back(source);
    return dirs;
}

std::vector<std::string> named_files(const std::string& folder) {
    std::vector<std::string> names;
    for (const auto& dir : search_dirs(folder)) {
        DIR* d = ::opendir(dir.c_str());
        if (!d) continue;
        while (const dirent* e = ::readdir(d)) {
            const std::string n = e->d_name;
            if (n.size() > 5 && n[0] != '.' && ends_with(n, ".toml") && is_file(dir + "/" + n))
                names.push_back(n.substr(0, n.size() - 5));
        }
        ::closedir(d);
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
}

std::string find_named_file(const std::string& name, const NamedFileKind& kind) {
    const std::string ext = lower(name.substr(std::min(name.size(), name.find_last_of('.'))));
    const char* other = ext == ".yaml" || ext == ".yml" ? "YAML" : ext == ".json" ? "JSON" : nullptr;
    if (other)
        throw InputError(kind.what + " '" + name + "': " + kind.plural + " are TOML, not " + other + " (" + kind.dump +
                         " prints one)");
    if (is_file(name)) return name;
    if (name.find('/') == std::string::npos)
        for (const auto& dir : search_dirs(kind.folder)) {
            if (is_file(dir + "/" + name + ".toml")) return dir + "/" + name + ".toml";
            if (is_file(dir + "/" + name)) return dir + "/" + name;
        }
    if (exists(name) || name.find('/') != std::string::npos) return name;
    const std::vector<std::string> names = named_files(kind.folder);
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    std::string msg = kind.what + " '" + name + "' not found: no such file, nor a name in " + kind.folder + "/";
    if (!names.empty()) msg += " (" + list + ")";
    std::string base = ends_with(lower(name), ".toml") ? name.substr(0, name.size() - 5) : name;
    const std::vector<std::string> near = nearest_names(base, names);
    if (!near.empty()) msg += "; did you mean " + or_list([&] {
        std::vector<std::string> q;
        for (const auto& n : near) q.push_back("'" + n + "'");
        return q;
    }()) + "?";
    throw InputError(msg);
}

}  // namespace raplas
