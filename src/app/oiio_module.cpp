// raplas_oiio: every OpenImageIO call, behind the C interface of
// oiio_module.hpp (a MODULE library that raplas loads when it needs it).
#include "oiio_module.hpp"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <memory>
#include <string>

namespace {

int fail(char* err, std::size_t size, const std::string& why) {
    if (size > 0) std::snprintf(err, size, "%s", why.c_str());
    return 1;
}

int write_rgb8(const char* path, int width, int height, const std::uint8_t* pixels, char* err, std::size_t err_size) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return fail(err, err_size, OIIO::geterror());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("Software", "raplas");
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels) || !out->close())
        return fail(err, err_size, out->geterror());
    return 0;
}

int read_rgb8(const char* path, int* width, int* height, void* ctx, std::uint8_t* (*alloc)(void*, std::size_t),
              char* err, std::size_t err_size) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return fail(err, err_size, OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    *width = spec.width;
    *height = spec.height;
    std::uint8_t* px = alloc(ctx, std::size_t(spec.width) * std::size_t(spec.height) * 3);
    if (!px) return fail(err, err_size, "image too large");
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px)) return fail(err, err_size, in->geterror());
    in->close();
    return 0;
}

struct Anim {
    std::unique_ptr<OIIO::ImageOutput> out;
    std::string path;
    OIIO::ImageSpec spec;
    int frames = 0;
};

void* anim_open(const char* path, int width, int height, int fps_num, int fps_den, char* err, std::size_t err_size) {
    auto a = std::make_unique<Anim>();
    a->out = OIIO::ImageOutput::create(path);
    if (!a->out) return fail(err, err_size, OIIO::geterror()), nullptr;
    if (!a->out->supports("multiimage") || !a->out->supports("appendsubimage"))
        return fail(err, err_size, std::string(a->out->format_name()) + " holds one image, not an animation (use .gif)"),
               nullptr;
    a->path = path;
    a->spec = OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8);
    const int fps[2] = {fps_num, fps_den};
    a->spec.attribute("FramesPerSecond", OIIO::TypeRational, fps);
    a->spec.attribute("oiio:LoopCount", 0);
    a->spec.attribute("Software", "raplas");
    return a.release();
}

int anim_add(void* handle, const std::uint8_t* pixels, char* err, std::size_t err_size) {
    auto* a = static_cast<Anim*>(handle);
    const bool opened = a->frames == 0 ? a->out->open(a->path, a->spec)
                                       : a->out->open(a->path, a->spec, OIIO::ImageOutput::AppendSubimage);
    if (!opened || !a->out->write_image(OIIO::TypeDesc::UINT8, pixels)) return fail(err, err_size, a->out->geterror());
    ++a->frames;
    return 0;
}

int anim_close(void* handle, char* err, std::size_t err_size) {
    std::unique_ptr<Anim> a(static_cast<Anim*>(handle));
    if (a->frames > 0 && !a->out->close()) return fail(err, err_size, a->out->geterror());
    return 0;
}

const RaplasOiioApi api{kRaplasOiioAbi, write_rgb8, read_rgb8, anim_open, anim_add, anim_close};

}  // namespace

extern "C" __attribute__((visibility("default"))) const RaplasOiioApi* raplas_oiio_api() { return &api; }
