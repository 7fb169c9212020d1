#include "raplas/app/image_io.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "oiio_module.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"

// Where the image module is: beside the installed executable (GNUInstallDirs:
// bin -> lib/raplas), beside raplas in a build tree, and in the build tree
// that made this program (the test binaries), all set by CMakeLists.txt.
#ifndef RAPLAS_LIB_FROM_BIN
#define RAPLAS_LIB_FROM_BIN "../lib/raplas"
#endif
#ifndef RAPLAS_OIIO_MODULE
#define RAPLAS_OIIO_MODULE ""
#endif

namespace raplas {

namespace {

constexpr const char* kModuleName = "raplas_oiio.so";

std::vector<std::string> module_candidates() {
    std::vector<std::string> paths;
    const std::string dir = executable_dir();
    if (!dir.empty()) {
        paths.push_back(dir + RAPLAS_LIB_FROM_BIN + "/" + kModuleName);
        paths.push_back(dir + kModuleName);
    }
    if (*RAPLAS_OIIO_MODULE && std::find(paths.begin(), paths.end(), RAPLAS_OIIO_MODULE) == paths.end())
        paths.emplace_back(RAPLAS_OIIO_MODULE);
    return paths;
}

const RaplasOiioApi& oiio() {
    static const RaplasOiioApi* api = [] {
        std::string looked;
        for (const std::string& path : module_candidates()) {
            looked += (looked.empty() ? "" : ", ") + path;
            if (!is_file(path)) continue;
            void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            if (!handle) throw std::runtime_error(std::string("cannot load the image module: ") + ::dlerror());
            auto entry = reinterpret_cast<const RaplasOiioApi* (*)()>(::dlsym(handle, "raplas_oiio_api"));
            const RaplasOiioApi* a = entry ? entry() : nullptr;
            if (!a || a->abi != kRaplasOiioAbi)
                throw std::runtime_error(path + " is not this raplas's image module (reinstall raplas)");
            return a;
        }
        throw std::runtime_error(std::string("the image module ") + kModuleName + " is missing (looked at " + looked +
                                 "; reinstall raplas)");
    }();
    return *api;
}

void write_rgb8(const std::string& path, int w, int h, const std::vector<std::uint8_t>& px) {
    const RaplasOiioApi& io = oiio();
    write_atomically(path, [&](const std::string& tmp) {
        char err[512] = "";
        if (io.write_rgb8(tmp.c_str(), w, h, px.data(), err, sizeof err) != 0)
            throw InputError(path + ": cannot write image: " + err);
    });
}

std::uint8_t to_srgb8(float linear) {
    double x = std::clamp(double(linear), 0.0, 1.0);
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(s * 255.0));
}

std::vector<std::uint8_t> srgb8(const std::vector<float>& rgb) {
    std::vector<std::uint8_t> px(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) px[i] = to_srgb8(rgb[i]);
    return px;
}

}  // namespace

void write_rgb_image(const std::string& path, int width, int height, const std::vector<float>& rgb) {
    write_rgb8(path, width, height, srgb8(rgb));
}

AnimationWriter::AnimationWriter(const std::string& path, int width, int height, double fps)
    : path_(path), tmp_(temp_path_for(path)), pixels_(std::size_t(width) * std::size_t(height) * 3) {
    // The rate as a fraction with a denominator of 1000 (GIF keeps hundredths of a second).
    const int den = 1000, num = std::max(1, int(std::lround(fps * den)));
    char err[512] = "";
    anim_ = oiio().anim_open(tmp_.c_str(), width, height, num, den, err, sizeof err);
    if (!anim_) {
        std::remove(tmp_.c_str());
        throw InputError(path + ": cannot write an animation: " + err);
    }
}

AnimationWriter::~AnimationWriter() {
    if (!anim_) return;
    char err[512] = "";
    oiio().anim_close(anim_, err, sizeof err);
    std::remove(tmp_.c_str());
}

void AnimationWriter::add(const std::vector<float>& rgb) {
    if (rgb.size() != pixels_) throw InputError(path_ + ": the frames of an animation must all have one size");
    char err[512] = "";
    if (oiio().anim_add(anim_, srgb8(rgb).data(), err, sizeof err) != 0)
        throw InputError(path_ + ": cannot write an animation: " + err);
}

void AnimationWriter::finish() {
    char err[512] = "";
    void* a = anim_;
    anim_ = nullptr;
    if (oiio().anim_close(a, err, sizeof err) != 0) {
        std::remove(tmp_.c_str());
        throw InputError(path_ + ": cannot write an animation: " + err);
    }
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
        std::remove(tmp_.c_str());
        throw InputError(path_ + ": cannot write an animation: cannot rename the temporary file into place");
    }
}

void write_heatmap(const std::string& path, int width, int height, const std::vector<std::uint64_t>& work) {
    std::uint64_t mx = 0;
    for (auto v : work) mx = std::max(mx, v);
    const double lmax = std::log1p(double(mx));
    std::vector<std::uint8_t> px(work.size() * 3);
    for (std::size_t i = 0; i < work.size(); ++i) {
        double x = lmax > 0 ? std::log1p(double(work[i])) / lmax : 0.0;  // 0..1
        // black -> purple -> orange -> yellow-white
        double r = std::clamp(1.5 * x, 0.0, 1.0);
        double g = std::clamp(1.8 * x - 0.6, 0.0, 1.0);
        double b = std::clamp(x < 0.4 ? 1.5 * x : 1.0 - 1.5 * (x - 0.4), 0.0, 1.0) * (x > 0 ? 1 : 0);
        if (x >= 0.9) b = (x - 0.9) * 8.0;
        px[i * 3] = std::uint8_t(std::lround(r * 255));
        px[i * 3 + 1] = std::uint8_t(std::lround(g * 255));
        px[i * 3 + 2] = std::uint8_t(std::lround(std::clamp(b, 0.0, 1.0) * 255));
    }
    write_rgb8(path, width, height, px);
}

void load_image_module() { oiio(); }

std::vector<std::uint8_t> read_rgb8(const std::string& path, int& width, int& height) {
    std::vector<std::uint8_t> px;
    auto alloc = [](void* ctx, std::size_t bytes) -> std::uint8_t* {
        auto* v = static_cast<std::vector<std::uint8_t>*>(ctx);
        v->resize(bytes);
        return v->data();
    };
    char err[512] = "";
    if (oiio().read_rgb8(path.c_str(), &width, &height, &px, alloc, err, sizeof err) != 0)
        throw InputError(path + ": cannot read image: " + err);
    return px;
}

}  // namespace raplas
