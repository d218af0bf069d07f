// hairscatter examples — OpenEXR and PNG output.
#include "image_io.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

// The one translation unit that compiles stb_image_write's implementation.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace hairscatter_examples {

void write_exr_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb,
                   const std::vector<std::pair<std::string, std::string>>& attributes) {
    if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * std::size_t(height) * 3)
        throw std::runtime_error("cannot write " + path + ": the pixel buffer does not match " +
                                 std::to_string(width) + " x " + std::to_string(height) + " RGB");
    try {
        Imf::Header header(width, height);
        const char* names[3] = {"R", "G", "B"};
        for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));

        // OpenEXR reads its channels as strided slices of the interleaved array.
        Imf::FrameBuffer frame;
        const std::size_t xstride = 3 * sizeof(float), ystride = xstride * std::size_t(width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(rgb.data()));
        for (int c = 0; c < 3; ++c)
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + std::size_t(c) * sizeof(float), xstride, ystride));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot write " + path + ": " + e.what());
    }
}

void write_png_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
    if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * std::size_t(height) * 3)
        throw std::runtime_error("cannot write " + path + ": the pixel buffer does not match its size");
    if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
        throw std::runtime_error("cannot write " + path);
}

std::uint8_t srgb8(double linear) {
    const double x = linear > 0.0 ? std::min(linear, 1.0) : 0.0;  // NaN and negatives show black
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(255.0 * s));
}

}  // namespace hairscatter_examples
