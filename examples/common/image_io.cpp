// hairscatter examples — OpenEXR and PNG output.
#include "image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>

#if defined(_WIN32)
#include <process.h>
#define HAIRSCATTER_GETPID _getpid
#else
#include <unistd.h>
#define HAIRSCATTER_GETPID getpid
#endif

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

// The one translation unit that compiles stb_image_write's implementation.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace hairscatter_examples {

namespace {

// A temporary file next to path: removed by the destructor unless commit() renamed it.
class TempFile {
  public:
    explicit TempFile(const std::string& path)
        : path_(path), temp_(path + ".tmp-" + std::to_string(long(HAIRSCATTER_GETPID()))) {}
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    ~TempFile() {
        if (!committed_) std::remove(temp_.c_str());
    }
    const std::string& name() const { return temp_; }
    void commit() {
        // std::rename replaces an existing target atomically on POSIX.
        if (std::rename(temp_.c_str(), path_.c_str()) != 0)
            throw std::runtime_error("cannot write " + path_ + ": renaming " + temp_ + " failed: " +
                                     std::strerror(errno));
        committed_ = true;
    }

  private:
    std::string path_, temp_;
    bool committed_ = false;
};

void check_size(const std::string& path, int width, int height, std::size_t values) {
    if (width <= 0 || height <= 0 || values != std::size_t(width) * std::size_t(height) * 3)
        throw std::runtime_error("cannot write " + path + ": the pixel buffer does not match " +
                                 std::to_string(width) + " x " + std::to_string(height) + " RGB");
}

// The EXR itself, to file (no rename); throws naming `shown` (the target path).
void exr_to(const std::string& file, const std::string& shown, int width, int height, const std::vector<float>& rgb,
            const std::vector<std::pair<std::string, std::string>>& attributes) {
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
        Imf::OutputFile out(file.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(height);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot write " + shown + ": " + e.what());
    }
}

// stb_image_write through a FILE we own, so that a failed fwrite or fclose (a full disk
// shows there) is an error and not a silently short file.
void png_to(const std::string& file, const std::string& shown, int width, int height,
            const std::vector<std::uint8_t>& rgb) {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + shown + ": " + std::strerror(errno));
    struct Sink {
        std::FILE* f;
        bool ok;
    } sink{f, true};
    const int encoded = stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
            Sink* s = static_cast<Sink*>(ctx);
            if (s->ok && std::fwrite(data, 1, std::size_t(size), s->f) != std::size_t(size)) s->ok = false;
        },
        &sink, width, height, 3, rgb.data(), width * 3);
    const bool flushed = std::fflush(f) == 0;
    const int err = errno;
    const bool closed = std::fclose(f) == 0;
    if (!encoded || !sink.ok || !flushed || !closed)
        throw std::runtime_error("cannot write " + shown + ": " + (encoded ? std::strerror(err) : "PNG encoding failed"));
}

}  // namespace

void write_exr_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb,
                   const std::vector<std::pair<std::string, std::string>>& attributes) {
    check_size(path, width, height, rgb.size());
    TempFile temp(path);
    exr_to(temp.name(), path, width, height, rgb, attributes);
    temp.commit();
}

void write_png_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
    check_size(path, width, height, rgb.size());
    TempFile temp(path);
    png_to(temp.name(), path, width, height, rgb);
    temp.commit();
}

void write_exr_png_pair(const std::string& exr_path, const std::string& png_path, int width, int height,
                        const std::vector<float>& rgb,
                        const std::vector<std::pair<std::string, std::string>>& attributes,
                        const std::vector<std::uint8_t>& png_rgb) {
    check_size(exr_path, width, height, rgb.size());
    check_size(png_path, width, height, png_rgb.size());
    TempFile exr(exr_path), png(png_path);
    exr_to(exr.name(), exr_path, width, height, rgb, attributes);
    png_to(png.name(), png_path, width, height, png_rgb);
    exr.commit();
    png.commit();
}

std::uint8_t srgb8(double linear) {
    const double x = linear > 0.0 ? std::min(linear, 1.0) : 0.0;  // NaN and negatives show black
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(255.0 * s));
}

}  // namespace hairscatter_examples
