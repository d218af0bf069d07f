// lobe_explorer — the two image types: linear f values and an 8-bit sRGB preview.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace lobe_explorer {

// Linear RGB f(wo, wi), row-major, row 0 at the top.
struct LinearImage {
    int width = 0, height = 0;
    std::vector<glm::dvec3> pixels;

    LinearImage(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h)) {}
    glm::dvec3& at(int x, int y) { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    const glm::dvec3& at(int x, int y) const {
        return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
};

// 8-bit RGB picture (the PNG), row-major, row 0 at the top. Writes outside are dropped,
// so text and marks may run off an edge.
struct Canvas {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;

    Canvas(int w, int h, Rgb8 background) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3) {
        fill_rect(0, 0, w, h, background);
    }
    void set(int x, int y, Rgb8 c) {
        if (x < 0 || y < 0 || x >= width || y >= height) return;
        std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
    }
    void fill_rect(int x0, int y0, int x1, int y1, Rgb8 c) {  // [x0, x1) × [y0, y1)
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) set(x, y, c);
    }
};

}  // namespace lobe_explorer
