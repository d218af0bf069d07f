// hairscatter examples — image files shared by the examples: OpenEXR (linear float RGB)
// and PNG (8-bit RGB, through stb_image_write).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hairscatter_examples {

// Every writer below is atomic: it writes a temporary file next to the target
// (<path>.tmp-<pid>) and renames it over the target only once the whole image is written, so
// a full disk, a write error or a SIGTERM leaves the previous file (or none) in place, never a
// truncated or 0-byte one. A failed write removes its temporary file.

// Writes an RGB image of width × height pixels, row-major from the top, 3 floats per pixel
// (R, G, B), as 32-bit float channels with the given string attributes in the header.
// Throws std::runtime_error naming the path on failure.
void write_exr_rgb(const std::string& path, int width, int height, const std::vector<float>& rgb,
                   const std::vector<std::pair<std::string, std::string>>& attributes);

// Writes 8-bit RGB, 3 bytes per pixel, row-major from the top. Throws std::runtime_error.
void write_png_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

// The EXR and its PNG preview as a pair: both are written to temporary files first and
// renamed only when both succeeded, so a failure of either leaves the previous pair as it
// was. Each file is atomic alone; the pair is not: a kill between the two renames leaves
// the new EXR beside the old PNG. Both therefore carry the pair's id, pair_id(rgb, png_rgb)
// (the EXR as the string attribute kPairIdKey, the PNG as a tEXt chunk of that keyword):
// a reader whose two ids differ holds files of two renders. Returns the id.
std::string write_exr_png_pair(const std::string& exr_path, const std::string& png_path, int width, int height,
                               const std::vector<float>& rgb,
                               const std::vector<std::pair<std::string, std::string>>& attributes,
                               const std::vector<std::uint8_t>& png_rgb);

// The keyword of the pair id in both files.
inline constexpr const char* kPairIdKey = "hairscatter:pair_id";

// A pair's id: 16 hex digits of a 64-bit FNV-1a hash of the EXR's pixels and the PNG's
// bytes, so the same render (and preview exposure) always gets the same id.
std::string pair_id(const std::vector<float>& rgb, const std::vector<std::uint8_t>& png_rgb);

// The pair id stored in an EXR or a PNG written by write_exr_png_pair ("" when the file
// has none). Throws std::runtime_error naming the path when it cannot be read.
std::string read_pair_id(const std::string& path);

// Linear [0, 1] to the sRGB transfer curve, 8 bits (values outside are clamped).
std::uint8_t srgb8(double linear);

}  // namespace hairscatter_examples
