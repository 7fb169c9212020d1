// raplas_oiio: every OpenImageIO call, behind the C interface of
// oiio_module.hpp (a MODULE library that raplas loads when it needs it).
#include "oiio_module.hpp"

#include <OpenImageIO/imageio.h>

#include <cstdio>
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

const RaplasOiioApi api{kRaplasOiioAbi, write_rgb8, read_rgb8};

}  // namespace

extern "C" __attribute__((visibility("default"))) const RaplasOiioApi* raplas_oiio_api() { return &api; }
