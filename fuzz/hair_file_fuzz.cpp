// libFuzzer target: the renderer's .hair loader (examples/render/hair_file.cpp) on any bytes.
// Every input either parses into a consistent HairFile or throws HairFileError; a parsed
// file serialises and parses back to the same counts. Anything else (a crash, a sanitizer
// report, another exception, an inconsistent result) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hair_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<unsigned char> bytes(data, data + size);
    render::HairFile h;
    try {
        h = render::parse_hair(bytes, "fuzz.hair");
    } catch (const render::HairFileError&) {
        return 0;
    }
    std::size_t total = 0;
    for (std::uint32_t s : h.segments) total += std::size_t(s) + 1;
    if (total != h.points.size()) std::abort();
    if (!h.thickness.empty() && h.thickness.size() != h.points.size()) std::abort();
    if (h.strands().size() != h.strand_count()) std::abort();
    const render::HairFile r = render::parse_hair(render::serialize_hair(h), "round trip");
    if (r.points.size() != h.points.size() || r.segments != h.segments) std::abort();
    return 0;
}
