// The C interface of raplas_oiio, the module that holds every OpenImageIO call.
// OpenImageIO links about 250 shared libraries, whose loading took 0.45 s at
// every start of a program linked with it; raplas loads the module with
// dlopen() only when it reads or writes an image (src/app/image_io.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" {

// Raised whenever the functions below change.
inline constexpr int kRaplasOiioAbi = 2;

struct RaplasOiioApi {
    int abi;
    // Writes W x H 8-bit RGB pixels to path, in the format its extension names.
    // 0 on success; else the reason, one line, in err (err_size bytes).
    int (*write_rgb8)(const char* path, int width, int height, const std::uint8_t* pixels, char* err,
                      std::size_t err_size);
    // Reads an image as 8-bit RGB into a buffer of width * height * 3 bytes
    // that alloc(ctx, bytes) returns (nullptr: give up). 0 on success, else
    // the reason in err.
    int (*read_rgb8)(const char* path, int* width, int* height, void* ctx,
                     std::uint8_t* (*alloc)(void* ctx, std::size_t bytes), char* err, std::size_t err_size);
    // An animation (GIF, or any format OpenImageIO writes several subimages
    // to): opened for W x H frames at fps_num / fps_den frames per second,
    // looping; frames added one at a time as 8-bit RGB; closed. open returns
    // nullptr and add and close non-zero on failure, the reason in err; close
    // frees the handle in every case.
    void* (*anim_open)(const char* path, int width, int height, int fps_num, int fps_den, char* err,
                       std::size_t err_size);
    int (*anim_add)(void* anim, const std::uint8_t* pixels, char* err, std::size_t err_size);
    int (*anim_close)(void* anim, char* err, std::size_t err_size);
};

// The module's one exported symbol.
const RaplasOiioApi* raplas_oiio_api();
}
