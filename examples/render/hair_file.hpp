// render — Cem Yuksel's open .hair format (www.cemyuksel.com/research/hairmodels/):
// a 128-byte little-endian header followed by optional arrays.
//
//   bytes  0–3    "HAIR"
//          4–7    number of strands                       (uint32)
//          8–11   total number of points                  (uint32)
//         12–15   which arrays follow, bit flags          (uint32):
//                 1 segments, 2 points, 4 thickness, 8 transparency, 16 colours
//         16–19   default segments per strand             (uint32)
//         20–23   default thickness                       (float)
//         24–27   default transparency                    (float)
//         28–39   default colour                          (3 floats)
//         40–127  free-form information                   (88 chars)
//   then, in this order and only if flagged: segments (uint16 per strand), points
//   (3 floats per point), thickness (float per point), transparency (float per point),
//   colours (3 floats per point). A strand of s segments has s + 1 points; the point
//   count must equal Σ (s + 1). Thickness is the fiber's diameter.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace render {

// A malformed or unreadable .hair file; what() names the file and what is wrong.
class HairFileError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct HairFile {
    std::vector<std::uint32_t> segments;  // per strand (filled from the default if absent)
    std::vector<glm::vec3> points;        // all strands' points, strand after strand
    std::vector<float> thickness;         // per point, or empty: default_thickness
    std::vector<float> transparency;      // per point, or empty
    std::vector<glm::vec3> colors;        // per point, or empty
    float default_thickness = 1.0f;
    float default_transparency = 0.0f;
    glm::vec3 default_color{1.0f};
    std::string info;

    std::size_t strand_count() const { return segments.size(); }
    // The strands as polylines.
    std::vector<std::vector<glm::vec3>> strands() const;
};

// Limits that reject absurd headers before anything is allocated.
inline constexpr std::uint32_t kHairMaxStrands = 50'000'000;
inline constexpr std::uint32_t kHairMaxPoints = 500'000'000;

// Parses a whole file held in memory; `name` is used in error messages.
HairFile parse_hair(const std::vector<unsigned char>& bytes, const std::string& name);
HairFile read_hair_file(const std::string& path);

// Serialises with every per-point array that is non-empty (and the segments array).
std::vector<unsigned char> serialize_hair(const HairFile& hair);
void write_hair_file(const std::string& path, const HairFile& hair);

}  // namespace render
