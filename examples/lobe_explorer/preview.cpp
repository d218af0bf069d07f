// lobe_explorer — the PNG preview.
#include "preview.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

// stb_easy_font: a public-domain, all-static ASCII font made of rectangles; enough to
// label axes without a font file.
#include <stb_easy_font.h>

namespace lobe_explorer {
namespace {

constexpr Rgb8 kBackground{24, 24, 28};
constexpr Rgb8 kText{225, 225, 225};
constexpr Rgb8 kFrame{110, 110, 120};
constexpr Rgb8 kMarker{255, 140, 40};

// Nine samples of matplotlib's viridis (perceptually uniform, readable in grey and by
// colour-blind viewers), interpolated linearly.
Rgb8 viridis(double t) {
    static constexpr unsigned char kStops[9][3] = {
        {68, 1, 84},    {71, 44, 122},  {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
        {39, 173, 129}, {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
    t = std::clamp(t, 0.0, 1.0) * 8.0;
    const int i = std::min(int(t), 7);
    const double u = t - i;
    auto mix = [&](int c) { return std::uint8_t(std::lround((1 - u) * kStops[i][c] + u * kStops[i + 1][c])); };
    return {mix(0), mix(1), mix(2)};
}

std::uint8_t srgb8(double linear) {
    const double x = std::clamp(linear, 0.0, 1.0);
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(255.0 * s));
}

// Maps f to a display colour; the log map needs the image maximum.
class ToneMapper {
  public:
    ToneMapper(const PreviewOptions& o, double max_luminance)
        : o_(o), log_max_(std::log10(max_luminance > 0 ? max_luminance : 1.0)),
          gain_(std::exp2(o.exposure)) {}

    double log_max() const { return log_max_; }

    Rgb8 operator()(const glm::dvec3& f) const {
        if (o_.tone == ToneMap::kLog) {
            const double y = luminance(f);
            // Below the range (or f = 0) shows the colour map's darkest end.
            const double t = y > 0 ? (std::log10(y) - log_max_) / o_.decades + 1.0 : 0.0;
            return viridis(t);
        }
        auto reinhard = [&](double x) { x = std::max(x, 0.0) * gain_; return srgb8(x / (1.0 + x)); };
        return {reinhard(f.r), reinhard(f.g), reinhard(f.b)};
    }

  private:
    const PreviewOptions& o_;
    double log_max_, gain_;
};

// --- text ------------------------------------------------------------------------------

int text_width(const std::string& s, int scale) {
    std::vector<char> buf(s.begin(), s.end());
    buf.push_back('\0');
    return stb_easy_font_width(buf.data()) * scale;
}

// Cap height of stb_easy_font's glyphs in font units (digits and capitals span y 0..7).
constexpr int kCapHeight = 7;
constexpr int kLineHeight = 12;

// Draws s with the top of its capitals at y.
void draw_text(Canvas& canvas, int x, int y, const std::string& s, Rgb8 color, int scale) {
    std::vector<char> text(s.begin(), s.end());
    text.push_back('\0');
    std::vector<char> vertices(600 * (s.size() + 1));  // the header's estimate is ~270 B/char
    const int quads = stb_easy_font_print(0, 0, text.data(), nullptr, vertices.data(), int(vertices.size()));
    for (int q = 0; q < quads; ++q) {
        float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
        for (int v = 0; v < 4; ++v) {  // each vertex: x, y, z as float, then 4 colour bytes
            float xy[2];
            std::memcpy(xy, vertices.data() + (4 * q + v) * 16, sizeof(xy));
            x0 = std::min(x0, xy[0]);
            x1 = std::max(x1, xy[0]);
            y0 = std::min(y0, xy[1]);
            y1 = std::max(y1, xy[1]);
        }
        const float k = float(scale);
        canvas.fill_rect(x + int(std::lround(x0 * k)), y + int(std::lround(y0 * k)), x + int(std::lround(x1 * k)),
                         y + int(std::lround(y1 * k)), color);
    }
}

// Greedy word wrap of text into lines at most max_width pixels wide (a single word
// wider than that gets a line of its own).
std::vector<std::string> wrap(const std::string& text, int max_width, int scale) {
    std::vector<std::string> lines;
    std::string line, word;
    auto flush_word = [&] {
        if (word.empty()) return;
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && text_width(candidate, scale) > max_width) {
            lines.push_back(line);
            line = word;
        } else {
            line = candidate;
        }
        word.clear();
    };
    for (char ch : text) {
        if (ch == ' ')
            flush_word();
        else
            word += ch;
    }
    flush_word();
    if (!line.empty()) lines.push_back(line);
    return lines;
}

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), fmt, v);
    return buf;
}

}  // namespace

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

Canvas make_preview(const LinearImage& f, const PreviewOptions& o) {
    double max_y = 0;
    for (const glm::dvec3& p : f.pixels) max_y = std::max(max_y, luminance(p));
    const ToneMapper tone(o, max_y);
    const int w = f.width, h = f.height;

    if (!o.annotate) {
        Canvas c(w, h, kBackground);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) c.set(x, y, tone(f.at(x, y)));
        return c;
    }

    // Font scale: 2 at the default 720 × 360, never below 1 or above 3.
    const int s = std::clamp(int(std::lround(std::min(w / 360.0, h / 180.0))), 1, 3);
    const int pad = 6 * s, tick = 4 * s, line = kLineHeight * s, cap = kCapHeight * s;
    const bool bar = o.tone == ToneMap::kLog;
    const int bar_w = 12 * s;

    const int left = pad + text_width("-90", s) + tick + 2 * s;
    const int marker_gap = 2 * s, marker = 5 * s;
    const int right = marker_gap + marker + (bar ? 8 * s + bar_w + tick + 2 * s + text_width("1e-10", s) : 0) + pad;
    const int canvas_w = left + w + right;

    // Text above the plot (the title, then the y axis' name) and below it (the x axis'
    // name and the marker's meaning), wrapped to the canvas.
    std::vector<std::string> above, below;
    const int text_w = canvas_w - 2 * pad;
    for (const std::string& t : o.title)
        for (std::string& l : wrap(t, text_w, s)) above.push_back(std::move(l));
    for (std::string& l : wrap("theta_i (deg), +90 = along the fiber tangent (root to tip)", text_w, s))
        above.push_back(std::move(l));
    for (const char* t : {"phi = phi_i - phi_o (deg): 0 = backward (R, TRT), +-180 = forward (TT)",
                          "orange mark: theta_i = -theta_o, the specular cone"})
        for (std::string& l : wrap(t, text_w, s)) below.push_back(std::move(l));

    const int top = pad + int(above.size()) * line;
    const int bottom = tick + 2 * s + line + int(below.size()) * line + pad;
    Canvas c(canvas_w, top + h + bottom, kBackground);
    const int ox = left, oy = top;

    for (std::size_t i = 0; i < above.size(); ++i) draw_text(c, pad, pad + int(i) * line, above[i], kText, s);

    // The plot and its frame.
    c.fill_rect(ox - 1, oy - 1, ox + w + 1, oy + h + 1, kFrame);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) c.set(ox + x, oy + y, tone(f.at(x, y)));

    // φ ticks every 45°, or 90° or 180° when the labels would not fit; θi ticks every
    // 30°, or 90° on a short image.
    const int phi_gap = text_width("-180", s) + 3 * s;
    const int phi_step = w >= 8 * phi_gap ? 45 : (w >= 4 * phi_gap ? 90 : 180);
    const int theta_step = h >= 6 * (cap + 3 * s) ? 30 : 90;
    for (int deg = -180; deg <= 180; deg += phi_step) {
        const int x = std::min(ox + int(std::lround((deg + 180) / 360.0 * w)), ox + w - 1);
        c.fill_rect(x, oy + h + 1, x + 1, oy + h + 1 + tick, kFrame);
        const std::string label = std::to_string(deg);
        draw_text(c, x - text_width(label, s) / 2, oy + h + tick + 2 * s, label, kText, s);
    }
    for (int deg = -90; deg <= 90; deg += theta_step) {
        const int y = std::min(oy + int(std::lround((90 - deg) / 180.0 * h)), oy + h - 1);
        c.fill_rect(ox - 1 - tick, y, ox - 1, y + 1, kFrame);
        const std::string label = std::to_string(deg);
        draw_text(c, ox - 1 - tick - 2 * s - text_width(label, s), y - cap / 2, label, kText, s);
    }
    const int caption = oy + h + tick + 2 * s + line;
    for (std::size_t i = 0; i < below.size(); ++i) draw_text(c, pad, caption + int(i) * line, below[i], kText, s);

    // The specular cone θi = -θo: a small triangle pointing at the plot's right edge.
    const int my = oy + int(std::lround((90.0 + o.theta_o_deg) / 180.0 * h));
    for (int k = 0; k < marker; ++k)
        c.fill_rect(ox + w + 1 + marker_gap + k, my - k / 2, ox + w + 2 + marker_gap + k, my + k / 2 + 1, kMarker);

    if (bar) {
        const int bx = ox + w + 1 + marker_gap + marker + 8 * s;
        const double log_max = tone.log_max(), log_min = log_max - o.decades;
        c.fill_rect(bx - 1, oy - 1, bx + bar_w + 1, oy + h + 1, kFrame);
        for (int y = 0; y < h; ++y) c.fill_rect(bx, oy + y, bx + bar_w, oy + y + 1, viridis(1.0 - (y + 0.5) / h));
        draw_text(c, bx + (bar_w - text_width("f", s)) / 2, oy + h + tick + 2 * s, "f", kText, s);
        auto label_at = [&](double log_value, const std::string& text) {
            const int y = std::min(oy + int(std::lround((log_max - log_value) / o.decades * h)), oy + h - 1);
            c.fill_rect(bx + bar_w, y, bx + bar_w + tick, y + 1, kFrame);
            draw_text(c, bx + bar_w + tick + 2 * s, y - cap / 2, text, kText, s);
        };
        bool any = false;
        // Every decade, or every n-th one when they would be closer than a text line.
        const int every = std::max(1, int(std::ceil(line * o.decades / h)));
        const int k_top = int(std::floor(log_max));
        for (int k = k_top; k >= int(std::ceil(log_min)); k -= every) {
            label_at(k, "1e" + std::to_string(k));
            any = true;
        }
        if (!any) {  // a range narrower than one decade: label its ends
            label_at(log_max, format("%.3g", std::pow(10.0, log_max)));
            label_at(log_min, format("%.3g", std::pow(10.0, log_min)));
        }
    }
    return c;
}

}  // namespace lobe_explorer
