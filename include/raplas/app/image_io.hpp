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
// Per-pixel work counts -> false-colour heat map on a log scale (black = none).
void write_heatmap(const std::string& path, int width, int height, const std::vector<std::uint64_t>& work);
// Loads the image module now, so that a run which will write an image finds a
// missing module before its work rather than after.
void load_image_module();
// Reads an image back as 8-bit RGB (tests, comparisons).
std::vector<std::uint8_t> read_rgb8(const std::string& path, int& width, int& height);

}  // namespace raplas
