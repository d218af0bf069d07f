// render — reading and writing Cem Yuksel's .hair files, every field checked.
#include "hair_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace render {
namespace {

constexpr std::size_t kHeaderBytes = 128;
constexpr std::uint32_t kSegmentsBit = 1, kPointsBit = 2, kThicknessBit = 4, kTransparencyBit = 8, kColorsBit = 16;
constexpr std::uint32_t kKnownBits = 31;

// Little-endian reads from a byte buffer whose bounds the caller has checked.
std::uint32_t u32_at(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
float f32_at(const unsigned char* p) {
    const std::uint32_t u = u32_at(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}
void put_u32(std::vector<unsigned char>& b, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
}
void put_f32(std::vector<unsigned char>& b, float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put_u32(b, u);
}

}  // namespace

std::vector<std::vector<glm::vec3>> HairFile::strands() const {
    std::vector<std::vector<glm::vec3>> out;
    out.reserve(segments.size());
    std::size_t at = 0;
    for (std::uint32_t s : segments) {
        out.emplace_back(points.begin() + std::ptrdiff_t(at), points.begin() + std::ptrdiff_t(at + s + 1));
        at += std::size_t(s) + 1;
    }
    return out;
}

namespace {

HairFileError invalid(const std::string& name, const std::string& why) {
    return HairFileError("'" + name + "' is not a valid .hair file: " + why);
}

// What a header announces, and the file size that follows from it.
struct Header {
    std::uint32_t strands = 0, points = 0, flags = 0, default_segments = 0;
    std::uint64_t expected = 0;  // the whole file's bytes
};

bool valid_transparency(float t) { return std::isfinite(t) && t >= 0 && t <= 1; }
bool valid_color(const glm::vec3& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 && c.b >= 0;
}
std::string to_string(const glm::vec3& c) {
    return "(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

// The 128-byte header at b: every field checked, the defaults stored in h.
Header read_header(const unsigned char* b, HairFile& h, const std::string& name) {
    auto fail = [&](const std::string& why) { return invalid(name, why); };
    if (std::memcmp(b, "HAIR", 4) != 0) throw fail("it does not start with the magic bytes \"HAIR\"");
    Header hd;
    hd.strands = u32_at(b + 4), hd.points = u32_at(b + 8), hd.flags = u32_at(b + 12), hd.default_segments = u32_at(b + 16);
    const std::uint32_t strands = hd.strands, points = hd.points, flags = hd.flags;
    h.default_thickness = f32_at(b + 20);
    h.default_transparency = f32_at(b + 24);
    h.default_color = glm::vec3(f32_at(b + 28), f32_at(b + 32), f32_at(b + 36));
    for (std::size_t i = 40; i < kHeaderBytes && b[i] != 0; ++i) h.info.push_back(char(b[i]));

    if (flags & ~kKnownBits) throw fail("unknown bits in the array flags 0x" + [&] {
        char s[16];
        std::snprintf(s, sizeof s, "%x", flags);
        return std::string(s);
    }());
    if (!(flags & kPointsBit)) throw fail("the header says it holds no points array");
    if (strands > kHairMaxStrands)
        throw fail("strand count " + std::to_string(strands) + " exceeds the limit " + std::to_string(kHairMaxStrands));
    if (points > kHairMaxPoints)
        throw fail("point count " + std::to_string(points) + " exceeds the limit " + std::to_string(kHairMaxPoints));
    if (!(flags & kSegmentsBit) && hd.default_segments > 65535)
        throw fail("default segment count " + std::to_string(hd.default_segments) + " exceeds 65535");
    if (!(flags & kThicknessBit) && !(std::isfinite(h.default_thickness) && h.default_thickness > 0))
        throw fail("default thickness " + std::to_string(h.default_thickness) + " is not a positive number");
    if (!(flags & kTransparencyBit) && !valid_transparency(h.default_transparency))
        throw fail("default transparency " + std::to_string(h.default_transparency) + " is not a number in [0, 1]");
    if (!(flags & kColorsBit) && !valid_color(h.default_color))
        throw fail("default colour " + to_string(h.default_color) + " is not a finite colour >= 0");
    // With a per-point array the header's default is unused; keep a valid one so that the
    // file written back (which drops an empty array) reads again.
    if ((flags & kThicknessBit) && !(std::isfinite(h.default_thickness) && h.default_thickness > 0))
        h.default_thickness = 1.0f;
    if ((flags & kTransparencyBit) && !valid_transparency(h.default_transparency)) h.default_transparency = 0.0f;
    if ((flags & kColorsBit) && !valid_color(h.default_color)) h.default_color = glm::vec3(1.0f);

    // Every array's size follows from the header.
    const std::uint64_t per_point = 12u + ((flags & kThicknessBit) ? 4u : 0u) + ((flags & kTransparencyBit) ? 4u : 0u) +
                                    ((flags & kColorsBit) ? 12u : 0u);
    hd.expected = kHeaderBytes + ((flags & kSegmentsBit) ? 2ull * strands : 0ull) + per_point * std::uint64_t(points);
    return hd;
}

// The file's length against the header's arrays.
void check_size(std::uint64_t size, const Header& hd, const std::string& name) {
    if (size < hd.expected)
        throw invalid(name, "it has " + std::to_string(size) + " bytes but its header (" + std::to_string(hd.strands) +
                                " strands, " + std::to_string(hd.points) + " points) needs " +
                                std::to_string(hd.expected) + " (truncated, or the counts are wrong)");
    if (size > hd.expected)
        throw invalid(name, "it has " + std::to_string(size - hd.expected) +
                                " bytes after the arrays its header announces (wrong counts?)");
}

}  // namespace

HairFile parse_hair(const std::vector<unsigned char>& bytes, const std::string& name) {
    auto fail = [&](const std::string& why) { return invalid(name, why); };
    if (bytes.size() < kHeaderBytes)
        throw fail("it has " + std::to_string(bytes.size()) + " bytes, fewer than the 128-byte header (truncated?)");
    const unsigned char* b = bytes.data();
    HairFile h;
    const Header hd = read_header(b, h, name);
    const std::uint32_t strands = hd.strands, points = hd.points, flags = hd.flags, default_segments = hd.default_segments;
    // Check the file length before reading.
    check_size(bytes.size(), hd, name);

    // The strand count against the point count, before the segments array is allocated: a
    // 128-byte header claiming 50 M strands of a default length but 0 points passed the
    // size check above (no segments array, no points) and allocated 200 MB first.
    if (flags & kSegmentsBit) {
        if (strands > points)  // every strand has at least one point
            throw fail("its header claims " + std::to_string(strands) + " strands but only " + std::to_string(points) +
                       " points (each strand has at least one)");
    } else if (std::uint64_t(strands) * (std::uint64_t(default_segments) + 1) != points) {
        throw fail(std::to_string(strands) + " strands of " + std::to_string(default_segments) +
                   " segments add up to " + std::to_string(std::uint64_t(strands) * (default_segments + 1ull)) +
                   " points but the header says " + std::to_string(points));
    }

    std::size_t at = kHeaderBytes;
    h.segments.resize(strands);
    std::uint64_t total = 0;
    for (std::uint32_t i = 0; i < strands; ++i) {
        std::uint32_t s = default_segments;
        if (flags & kSegmentsBit) {
            s = std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8;
            at += 2;
        }
        h.segments[i] = s;
        total += std::uint64_t(s) + 1;
    }
    if (total != points)
        throw fail("its strands' segments add up to " + std::to_string(total) + " points but the header says " +
                   std::to_string(points));
    h.points.resize(points);
    for (std::uint32_t i = 0; i < points; ++i, at += 12) {
        h.points[i] = glm::vec3(f32_at(b + at), f32_at(b + at + 4), f32_at(b + at + 8));
        if (!(std::isfinite(h.points[i].x) && std::isfinite(h.points[i].y) && std::isfinite(h.points[i].z)))
            throw fail("point " + std::to_string(i) + " is not finite");
    }
    if (flags & kThicknessBit) {
        h.thickness.resize(points);
        for (std::uint32_t i = 0; i < points; ++i, at += 4) {
            h.thickness[i] = f32_at(b + at);
            if (!(std::isfinite(h.thickness[i]) && h.thickness[i] >= 0))
                throw fail("thickness of point " + std::to_string(i) + " is " + std::to_string(h.thickness[i]) +
                           ", not a finite number ≥ 0");
        }
    }
    if (flags & kTransparencyBit) {
        h.transparency.resize(points);
        for (std::uint32_t i = 0; i < points; ++i, at += 4) {
            h.transparency[i] = f32_at(b + at);
            if (!valid_transparency(h.transparency[i]))
                throw fail("transparency of point " + std::to_string(i) + " is " + std::to_string(h.transparency[i]) +
                           ", not a number in [0, 1]");
        }
    }
    if (flags & kColorsBit) {
        h.colors.resize(points);
        for (std::uint32_t i = 0; i < points; ++i, at += 12) {
            h.colors[i] = glm::vec3(f32_at(b + at), f32_at(b + at + 4), f32_at(b + at + 8));
            if (!valid_color(h.colors[i]))
                throw fail("colour of point " + std::to_string(i) + " is " + to_string(h.colors[i]) +
                           ", not a finite colour ≥ 0");
        }
    }
    return h;
}

// The header first: a file whose size differs from what it announces is refused before
// the arrays are read or allocated (a 1 GiB file cost 1 GB and 25 s before). A stream of
// unknown size (a pipe) is read no further than the header promises.
HairFile read_hair_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw HairFileError("cannot open .hair file '" + path + "'");
    f.seekg(0, std::ios::end);
    const std::streamoff size = f ? std::streamoff(f.tellg()) : std::streamoff(-1);  // -1: a pipe
    f.clear();
    f.seekg(0, std::ios::beg);
    f.clear();
    std::vector<unsigned char> bytes(kHeaderBytes);
    f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(kHeaderBytes));
    bytes.resize(std::size_t(f.gcount()));
    if (f.bad()) throw HairFileError("cannot read .hair file '" + path + "'");
    if (bytes.size() < kHeaderBytes) return parse_hair(bytes, path);  // names the short header
    HairFile header_only;
    const Header hd = read_header(bytes.data(), header_only, path);
    if (size >= 0) {
        check_size(std::uint64_t(size), hd, path);
        bytes.reserve(std::size_t(hd.expected));
    }
    // In chunks: from a pipe, no more is allocated than arrives.
    while (bytes.size() < hd.expected) {
        const std::size_t have = bytes.size(), most = std::size_t(1) << 24;
        const std::size_t chunk = hd.expected - have < most ? std::size_t(hd.expected - have) : most;
        bytes.resize(have + chunk);
        f.read(reinterpret_cast<char*>(bytes.data() + have), std::streamsize(chunk));
        bytes.resize(have + std::size_t(f.gcount()));
        if (f.bad()) throw HairFileError("cannot read .hair file '" + path + "'");
        if (std::size_t(f.gcount()) < chunk) check_size(bytes.size(), hd, path);  // truncated
    }
    if (f.peek() != std::ifstream::traits_type::eof())
        throw invalid(path, "it has bytes after the arrays its header announces (wrong counts?)");
    return parse_hair(bytes, path);
}

std::vector<unsigned char> serialize_hair(const HairFile& h) {
    std::uint64_t total = 0;
    for (std::uint32_t s : h.segments) {
        if (s > 65535) throw HairFileError("cannot write a strand of " + std::to_string(s) + " segments (max 65535)");
        total += std::uint64_t(s) + 1;
    }
    if (total != h.points.size()) throw HairFileError("cannot write: the segments do not add up to the points");
    auto per_point = [&](std::size_t n, const char* what) {
        if (n != 0 && n != h.points.size())
            throw HairFileError(std::string("cannot write: the ") + what + " array does not have one entry per point");
        return n != 0;
    };
    const bool thick = per_point(h.thickness.size(), "thickness"), transp = per_point(h.transparency.size(), "transparency"),
               color = per_point(h.colors.size(), "colour");
    std::uint32_t flags = kSegmentsBit | kPointsBit;
    if (thick) flags |= kThicknessBit;
    if (transp) flags |= kTransparencyBit;
    if (color) flags |= kColorsBit;

    std::vector<unsigned char> b(4);
    std::memcpy(b.data(), "HAIR", 4);
    put_u32(b, std::uint32_t(h.segments.size()));
    put_u32(b, std::uint32_t(h.points.size()));
    put_u32(b, flags);
    put_u32(b, h.segments.empty() ? 0u : h.segments[0]);
    put_f32(b, h.default_thickness);
    put_f32(b, h.default_transparency);
    for (int c = 0; c < 3; ++c) put_f32(b, h.default_color[c]);
    char info[88] = {};
    std::memcpy(info, h.info.data(), std::min<std::size_t>(h.info.size(), 87));
    b.insert(b.end(), info, info + 88);
    for (std::uint32_t s : h.segments) {
        b.push_back(static_cast<unsigned char>(s & 0xff));
        b.push_back(static_cast<unsigned char>(s >> 8));
    }
    for (const glm::vec3& p : h.points)
        for (int c = 0; c < 3; ++c) put_f32(b, p[c]);
    if (thick)
        for (float t : h.thickness) put_f32(b, t);
    if (transp)
        for (float t : h.transparency) put_f32(b, t);
    if (color)
        for (const glm::vec3& p : h.colors)
            for (int c = 0; c < 3; ++c) put_f32(b, p[c]);
    return b;
}

void write_hair_file(const std::string& path, const HairFile& hair) {
    const std::vector<unsigned char> b = serialize_hair(hair);
    std::ofstream f(path, std::ios::binary);
    if (!f) throw HairFileError("cannot write .hair file '" + path + "'");
    f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    if (!f) throw HairFileError("failed writing .hair file '" + path + "'");
}

}  // namespace render
