// lobe_explorer — OpenEXR and PNG output.
#include "image_io.hpp"

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

namespace lobe_explorer {

void write_exr(const std::string& path, const LinearImage& image,
               const std::vector<std::pair<std::string, std::string>>& attributes) {
    // OpenEXR wants its channels as separate strided slices of one float array.
    std::vector<float> rgb(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) rgb[3 * i + std::size_t(c)] = float(image.pixels[i][c]);

    try {
        Imf::Header header(image.width, image.height);
        const char* names[3] = {"R", "G", "B"};
        for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));

        Imf::FrameBuffer frame;
        const std::size_t xstride = 3 * sizeof(float), ystride = xstride * std::size_t(image.width);
        for (int c = 0; c < 3; ++c)
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb.data() + c),
                                              xstride, ystride));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot write " + path + ": " + e.what());
    }
}

void write_png(const std::string& path, const Canvas& canvas) {
    if (!stbi_write_png(path.c_str(), canvas.width, canvas.height, 3, canvas.rgb.data(), canvas.width * 3))
        throw std::runtime_error("cannot write " + path);
}

}  // namespace lobe_explorer
