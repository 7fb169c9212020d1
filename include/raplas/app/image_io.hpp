// All image output (OpenImageIO), written atomically. OpenImageIO is called
// through the raplas_oiio module, loaded on first use: a run that writes no
// image never loads it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raplas {

// Linear RGB floats (W*H*3) -> 8-bit sRGB PNG (or any format OIIO knows by extension).
void write_rgb_image(const std::string& path, int width, int height, const std::vector<float>& rgb);
// Frames of one size -> an animated image (GIF: OpenImageIO's multi-image
// formats), looping at `fps` frames per second, written to a temporary file
// beside `path` as frames come and renamed into place by finish(); a writer
// destroyed unfinished removes it. InputError naming the path otherwise.
class AnimationWriter {
public:
    AnimationWriter(const std::string& path, int width, int height, double fps);
    ~AnimationWriter();
    AnimationWriter(const AnimationWriter&) = delete;
    AnimationWriter& operator=(const AnimationWriter&) = delete;
    void add(const std::vector<float>& rgb);  // linear RGB floats, as write_rgb_image
    void finish();

private:
    std::string path_, tmp_;
    void* anim_ = nullptr;
    std::size_t pixels_ = 0;
};

// Per-pixel work counts -> false-colour heat map on a log scale (black = none).
void write_heatmap(const std::string& path, int width, int height, const std::vector<std::uint64_t>& work);
// Loads the image module now, so that a run which will write an image finds a
// missing module before its work rather than after.
void load_image_module();
// Reads an image back as 8-bit RGB (tests, comparisons).
std::vector<std::uint8_t> read_rgb8(const std::string& path, int& width, int& height);

}  // namespace raplas
