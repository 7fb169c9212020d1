// All image output (OpenImageIO), written atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raplas {

// Linear RGB floats (W*H*3) -> 8-bit sRGB PNG (or any format OIIO knows by extension).
void write_rgb_image(const std::string& path, int width, int height, const std::vector<float>& rgb);
// Per-pixel work counts -> false-colour heat map on a log scale (black = none).
void write_heatmap(const std::string& path, int width, int height, const std::vector<std::uint64_t>& work);
// Reads an image back as 8-bit RGB (tests, comparisons).
std::vector<std::uint8_t> read_rgb8(const std::string& path, int& width, int& height);

}  // namespace raplas
