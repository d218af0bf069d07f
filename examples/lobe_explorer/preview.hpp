// lobe_explorer — the PNG preview: tone mapping, colour map and axis annotation.
#pragma once

#include <string>
#include <vector>

#include "image.hpp"

namespace lobe_explorer {

enum class ToneMap {
    kLog,       // false colour of log10(luminance f) over `decades` below its maximum
    kReinhard,  // f · 2^exposure, Reinhard x / (1 + x) per channel, sRGB: shows the hue
};

struct PreviewOptions {
    ToneMap tone = ToneMap::kLog;
    double decades = 4.0;
    double exposure = 0.0;
    bool annotate = true;            // axes, ticks, colour bar and the title around the plot
    double theta_o_deg = 30.0;       // marks the specular cone θi = -θo on the right edge
    std::vector<std::string> title;  // lines printed above the plot
};

// The plot occupies exactly f.width × f.height pixels of the result (one per EXR pixel);
// with annotate it is framed by margins that hold the labels.
Canvas make_preview(const LinearImage& f, const PreviewOptions& options);

// Rec. 709 luminance, the scalar the log preview shows.
double luminance(const glm::dvec3& c);

}  // namespace lobe_explorer
