#include "raplas/app/image_io.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"

namespace raplas {

namespace {

void write_rgb8(const std::string& path, int w, int h, const std::vector<std::uint8_t>& px) {
    write_atomically(path, [&](const std::string& tmp) {
        auto out = OIIO::ImageOutput::create(tmp);
        if (!out) throw InputError(path + ": cannot write image: " + OIIO::geterror());
        OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("Software", "raplas");
        if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()) || !out->close())
            throw InputError(path + ": cannot write image: " + out->geterror());
    });
}

std::uint8_t to_srgb8(float linear) {
    double x = std::clamp(double(linear), 0.0, 1.0);
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(s * 255.0));
}

}  // namespace

void write_rgb_image(const std::string& path, int width, int height, const std::vector<float>& rgb) {
    std::vector<std::uint8_t> px(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) px[i] = to_srgb8(rgb[i]);
    write_rgb8(path, width, height, px);
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

std::vector<std::uint8_t> read_rgb8(const std::string& path, int& width, int& height) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError(path + ": cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width;
    height = spec.height;
    std::vector<std::uint8_t> px(std::size_t(width) * std::size_t(height) * 3);
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()))
        throw InputError(path + ": cannot read image: " + in->geterror());
    in->close();
    return px;
}

}  // namespace raplas
