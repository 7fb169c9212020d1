// fuzz_obj: the OBJ reader (raplas::load_obj_text: line-numbered validation,
// tinyobjloader, MTL materials).
//
// Input: OBJ text, optionally followed by a line "#%mtl"; everything after
// that line is the MTL file "fuzz.mtl" in a directory private to this
// process, which `mtllib fuzz.mtl` reads. MTL files are read from nowhere
// else: an input whose mtllib line contains '/' is loaded with MTL reading
// off. A mesh that loads must satisfy what the front end relies on.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_common.hpp"
#include "raplas/scene/mesh.hpp"

namespace {

const char* const kTarget = "fuzz_obj";

// Created on first use, removed at exit.
struct PrivateDir {
    std::string path;
    PrivateDir() {
        std::string tmpl = (std::filesystem::temp_directory_path() / "raplas_fuzz_obj_XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) raplas::fuzz::fail(kTarget, "cannot create a temporary directory");
        path = tmpl;
    }
    ~PrivateDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

const std::string& private_dir() {
    static const PrivateDir dir;
    return dir.path;
}

// True when a line that mentions mtllib (lines end at \n or \r) names a path.
bool mtllib_names_a_path(const std::string& obj) {
    std::size_t start = 0;
    while (start <= obj.size()) {
        std::size_t end = obj.find_first_of("\r\n", start);
        if (end == std::string::npos) end = obj.size();
        const std::string line = obj.substr(start, end - start);
        if (line.find("mtllib") != std::string::npos && line.find('/') != std::string::npos) return true;
        start = end + 1;
    }
    return false;
}

void check_mesh(const raplas::Mesh& m) {
    using raplas::fuzz::fail;
    if (m.triangles.empty()) fail(kTarget, "mesh without triangles");
    if (m.materials.empty()) fail(kTarget, "mesh without the default material");
    if (m.triangle_material.size() != m.triangles.size()) fail(kTarget, "one material per triangle expected");
    for (const auto& v : m.vertices)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fail(kTarget, "non-finite vertex");
    for (const auto& t : m.triangles)
        for (auto i : t)
            if (i >= m.vertices.size()) fail(kTarget, "triangle index out of range");
    for (auto mt : m.triangle_material)
        if (mt < 0 || static_cast<std::size_t>(mt) >= m.materials.size()) fail(kTarget, "material index out of range");
    for (const auto& mt : m.materials)
        if (!raplas::all_finite(mt.diffuse) || !raplas::all_finite(mt.emission)) fail(kTarget, "non-finite material");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
    std::string obj = raplas::fuzz::as_string(data, size);
    const std::string dir = private_dir();
    const std::string mtl_path = dir + "/fuzz.mtl";
    const std::string sep = "#%mtl\n";
    std::size_t cut = obj.rfind(sep, 0) == 0 ? 0 : obj.find("\n" + sep);
    if (cut != std::string::npos) {
        const std::size_t mtl_begin = cut + (cut == 0 ? sep.size() : sep.size() + 1);
        std::ofstream(mtl_path, std::ios::binary | std::ios::trunc) << obj.substr(mtl_begin);
        obj.resize(cut == 0 ? 0 : cut + 1);
    } else {
        std::remove(mtl_path.c_str());
    }
    const std::string mtl_dir = mtllib_names_a_path(obj) ? "" : dir;
    raplas::fuzz::guarded(kTarget, [&] { check_mesh(raplas::load_obj_text(obj, "fuzz.obj", mtl_dir)); });
    return 0;
}
