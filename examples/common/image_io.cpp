// hairscatter examples — OpenEXR and PNG output.
#include "image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
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
#include <ImfInputFile.h>
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

// PNG's CRC-32 (ISO 3309, as in the PNG specification's sample code) of a chunk's type
// and data.
std::uint32_t png_crc(const unsigned char* p, std::size_t n) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

void put_be32(std::vector<unsigned char>& b, std::uint32_t v) {
    for (int i = 3; i >= 0; --i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

// The 8-byte signature and the IHDR chunk (13 bytes of data) open every PNG; tEXt chunks
// may follow anywhere before IEND, so right after IHDR.
constexpr std::size_t kPngAfterIhdr = 8 + 4 + 4 + 13 + 4;

// A tEXt chunk: keyword, a zero byte, the text (Latin-1, no zero byte).
std::vector<unsigned char> png_text_chunk(const std::string& keyword, const std::string& text) {
    std::vector<unsigned char> body = {'t', 'E', 'X', 't'};
    body.insert(body.end(), keyword.begin(), keyword.end());
    body.push_back(0);
    body.insert(body.end(), text.begin(), text.end());
    std::vector<unsigned char> chunk;
    put_be32(chunk, std::uint32_t(body.size() - 4));
    chunk.insert(chunk.end(), body.begin(), body.end());
    put_be32(chunk, png_crc(body.data(), body.size()));
    return chunk;
}

// stb_image_write into memory, the text chunks inserted after IHDR, then through a FILE
// we own, so that a failed fwrite or fclose (a full disk shows there) is an error and not
// a silently short file.
void png_to(const std::string& file, const std::string& shown, int width, int height,
            const std::vector<std::uint8_t>& rgb, const std::vector<std::pair<std::string, std::string>>& text) {
    std::vector<unsigned char> png;
    const int encoded = stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
            auto* out = static_cast<std::vector<unsigned char>*>(ctx);
            const unsigned char* p = static_cast<const unsigned char*>(data);
            out->insert(out->end(), p, p + size);
        },
        &png, width, height, 3, rgb.data(), width * 3);
    if (!encoded || png.size() < kPngAfterIhdr) throw std::runtime_error("cannot write " + shown + ": PNG encoding failed");
    for (auto it = text.rbegin(); it != text.rend(); ++it) {
        const std::vector<unsigned char> chunk = png_text_chunk(it->first, it->second);
        png.insert(png.begin() + std::ptrdiff_t(kPngAfterIhdr), chunk.begin(), chunk.end());
    }
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + shown + ": " + std::strerror(errno));
    const bool written = std::fwrite(png.data(), 1, png.size(), f) == png.size();
    const bool flushed = std::fflush(f) == 0;
    const int err = errno;
    const bool closed = std::fclose(f) == 0;
    if (!written || !flushed || !closed) throw std::runtime_error("cannot write " + shown + ": " + std::strerror(err));
}

std::uint32_t be32_at(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | std::uint32_t(p[3]);
}

// The text of the first tEXt chunk with this keyword before the image data ("" if none).
std::string png_text(const std::string& path, const std::string& keyword) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot read " + path);
    unsigned char head[8];
    if (!f.read(reinterpret_cast<char*>(head), 8) || std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) != 0)
        throw std::runtime_error("cannot read " + path + ": not a PNG file");
    for (;;) {
        unsigned char h[8];
        if (!f.read(reinterpret_cast<char*>(h), 8)) return "";
        const std::uint32_t length = be32_at(h);
        const std::string type(reinterpret_cast<const char*>(h + 4), 4);
        if (type == "IDAT" || type == "IEND" || length > (1u << 24)) return "";
        std::string data(length, '\0');
        if (!f.read(&data[0], std::streamsize(length)) || !f.seekg(4, std::ios::cur)) return "";  // and the CRC
        if (type == "tEXt" && data.compare(0, keyword.size() + 1, keyword + std::string(1, '\0')) == 0)
            return data.substr(keyword.size() + 1);
    }
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
    png_to(temp.name(), path, width, height, rgb, {});
    temp.commit();
}

std::string pair_id(const std::vector<float>& rgb, const std::vector<std::uint8_t>& png_rgb) {
    std::uint64_t h = 1469598103934665603ull;
    auto add = [&](const void* data, std::size_t n) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    };
    add(rgb.data(), rgb.size() * sizeof(float));
    add(png_rgb.data(), png_rgb.size());
    char s[17];
    std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
    return s;
}

std::string write_exr_png_pair(const std::string& exr_path, const std::string& png_path, int width, int height,
                               const std::vector<float>& rgb,
                               const std::vector<std::pair<std::string, std::string>>& attributes,
                               const std::vector<std::uint8_t>& png_rgb) {
    check_size(exr_path, width, height, rgb.size());
    check_size(png_path, width, height, png_rgb.size());
    const std::string id = pair_id(rgb, png_rgb);
    std::vector<std::pair<std::string, std::string>> exr_attributes = attributes;
    exr_attributes.emplace_back(kPairIdKey, id);
    TempFile exr(exr_path), png(png_path);
    exr_to(exr.name(), exr_path, width, height, rgb, exr_attributes);
    png_to(png.name(), png_path, width, height, png_rgb, {{kPairIdKey, id}});
    exr.commit();
    png.commit();
    return id;
}

std::string read_pair_id(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    char magic[4] = {};
    if (!f.read(magic, 4)) throw std::runtime_error("cannot read " + path);
    f.close();
    if (std::memcmp(magic, "\x89PNG", 4) == 0) return png_text(path, kPairIdKey);
    try {
        Imf::InputFile in(path.c_str());
        const auto* id = in.header().findTypedAttribute<Imf::StringAttribute>(kPairIdKey);
        return id ? id->value() : std::string();
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot read " + path + ": " + e.what());
    }
}

std::uint8_t srgb8(double linear) {
    const double x = linear > 0.0 ? std::min(linear, 1.0) : 0.0;  // NaN and negatives show black
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(255.0 * s));
}

}  // namespace hairscatter_examples
