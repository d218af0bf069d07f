// render — environment lighting: lat-long maps (OpenEXR or the procedural studio) and
// their importance sampling.
#include "environment.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImathBox.h>

#include "sampling.hpp"

namespace render {

namespace {

// Rec. 709 luminance: what the eye weighs, so what the sampler should.
float luminance(const float* rgb) { return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2]; }

// φ in [0, 2π) of a direction: 0 toward +z, π/2 toward +x.
float azimuth(const glm::vec3& d) {
    const float phi = std::atan2(d.x, d.z);
    return phi < 0 ? phi + 2 * kPi : phi;
}

}  // namespace

Distribution1D::Distribution1D(std::vector<float> weights) : weights_(std::move(weights)) {
    const std::size_t n = weights_.size();
    cdf_.assign(n + 1, 0.0f);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sum += double(weights_[i]);
        cdf_[i + 1] = float(sum);
    }
    mean_ = float(sum / double(n));
    if (!(sum > 0)) throw std::invalid_argument("a piecewise-constant distribution needs a positive weight");
    for (std::size_t i = 1; i <= n; ++i) cdf_[i] = float(double(cdf_[i]) / sum);
    cdf_[n] = 1.0f;
}

Distribution1D::Sample Distribution1D::sample(float u) const {
    // The last bin whose cdf is ≤ u; zero-weight bins have zero width and are never chosen.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const int bin = std::clamp(int(it - cdf_.begin()) - 1, 0, size() - 1);
    const float lo = cdf_[std::size_t(bin)], width = cdf_[std::size_t(bin) + 1] - lo;
    // u − lo can round to width: keep x inside the bin.
    const float t = width > 0 ? std::min((u - lo) / width, 0.99999994f) : 0.5f;
    Sample s;
    s.bin = bin;
    s.x = (float(bin) + t) / float(size());
    s.pdf = pdf(bin);
    return s;
}

LatLongMap read_lat_long_exr(const std::string& path) {
    const std::string who = "--env " + path + ": ";
    if (!std::ifstream(path)) throw std::invalid_argument(who + "cannot open the file");
    LatLongMap m;
    m.name = path;
    try {
        Imf::InputFile in(path.c_str());
        const Imf::ChannelList& channels = in.header().channels();
        std::string found;
        for (auto c = channels.begin(); c != channels.end(); ++c) found += std::string(found.empty() ? "" : ", ") + c.name();
        for (const char* name : {"R", "G", "B"})
            if (!channels.findChannel(name))
                throw std::invalid_argument(who + "no " + name + " channel (a lat-long map needs R, G and B; the file has " +
                                            (found.empty() ? std::string("none") : found) + ")");
        const Imath::Box2i win = in.header().dataWindow();
        m.width = win.max.x - win.min.x + 1;
        m.height = win.max.y - win.min.y + 1;
        if (m.width != 2 * m.height)
            throw std::invalid_argument(who + "not a lat-long map: " + std::to_string(m.width) + " x " +
                                        std::to_string(m.height) + " pixels, the width should be twice the height");
        m.rgb.assign(std::size_t(m.width) * std::size_t(m.height) * 3, 0.0f);
        Imf::FrameBuffer frame;
        const std::size_t xs = 3 * sizeof(float), ys = xs * std::size_t(m.width);
        // OpenEXR addresses the buffer by absolute pixel coordinates of the data window.
        char* base = reinterpret_cast<char*>(m.rgb.data()) - std::ptrdiff_t(win.min.x) * std::ptrdiff_t(xs) -
                     std::ptrdiff_t(win.min.y) * std::ptrdiff_t(ys);
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + std::size_t(c) * sizeof(float), xs, ys));
        in.setFrameBuffer(frame);
        in.readPixels(win.min.y, win.max.y);
    } catch (const std::invalid_argument&) {
        throw;
    } catch (const std::exception& e) {
        throw std::invalid_argument(who + "cannot read it as OpenEXR (" + e.what() + ")");
    }
    for (std::size_t i = 0; i < m.rgb.size(); ++i)
        if (!(std::isfinite(m.rgb[i]) && m.rgb[i] >= 0)) {
            const std::size_t p = i / 3;
            throw std::invalid_argument(who + "pixel (" + std::to_string(p % std::size_t(m.width)) + ", " +
                                        std::to_string(p / std::size_t(m.width)) +
                                        ") is negative or not finite (radiance must be a finite value >= 0)");
        }
    return m;
}

LatLongMap make_studio_map(int width) {
    LatLongMap m;
    m.name = "studio";
    m.width = width;
    m.height = width / 2;
    m.rgb.assign(std::size_t(m.width) * std::size_t(m.height) * 3, 0.0f);
    // A softbox: a rectangle in (azimuth, elevation) around a centre, in degrees.
    struct Softbox {
        float phi, elevation, half_phi, half_elevation;
        glm::vec3 radiance;
    };
    const Softbox boxes[] = {
        {315.0f, 35.0f, 22.0f, 16.0f, {10.0f, 9.5f, 8.7f}},  // key: front left, above
        {130.0f, 25.0f, 5.0f, 30.0f, {10.0f, 10.7f, 11.4f}},  // rims: strips behind, out of frame
        {230.0f, 25.0f, 5.0f, 30.0f, {6.0f, 6.4f, 6.9f}},
        {65.0f, 10.0f, 14.0f, 14.0f, {2.0f, 2.0f, 2.1f}},     // fill: right, low
    };
    auto radiance = [&](float phi_deg, float elevation_deg) {
        // The studio's walls: dark floor, a soft horizon, a brighter ceiling.
        const float s = std::sin(elevation_deg * kPi / 180.0f);
        glm::vec3 L = s < 0 ? glm::mix(glm::vec3(0.05f), glm::vec3(0.02f), -s)
                            : glm::mix(glm::vec3(0.08f), glm::vec3(0.16f, 0.17f, 0.19f), s);
        for (const Softbox& b : boxes) {
            float dphi = std::abs(phi_deg - b.phi);
            dphi = std::min(dphi, 360.0f - dphi);
            if (dphi <= b.half_phi && std::abs(elevation_deg - b.elevation) <= b.half_elevation) L = b.radiance;
        }
        return L;
    };
    // 4 × 4 samples a pixel smooth the softboxes' edges.
    constexpr int k = 4;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            glm::vec3 sum(0);
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const float u = (float(x) + (float(i) + 0.5f) / k) / float(m.width);
                    const float v = (float(y) + (float(j) + 0.5f) / k) / float(m.height);
                    sum += radiance(360.0f * u, 90.0f - 180.0f * v);
                }
            for (int c = 0; c < 3; ++c)
                m.rgb[3 * (std::size_t(y) * std::size_t(m.width) + std::size_t(x)) + std::size_t(c)] = sum[c] / (k * k);
        }
    return m;
}

Environment::Environment(const glm::vec3& radiance) : constant_(radiance), any_(max3(radiance) > 0) {}

Environment::Environment(const LatLongMap& map, float rotate_deg, float intensity)
    : any_(true), width_(map.width), height_(map.height), rgb_(map.rgb), rotate_(rotate_deg * kPi / 180.0f) {
    for (float& v : rgb_) v *= intensity;
    // Row y covers θ in [y, y + 1) π / height: its solid angle is proportional to sin θ at
    // its centre (to first order), so the marginal weighs each row's sum by it.
    std::vector<float> rows(std::size_t(height_), 0.0f);
    conditional_.reserve(std::size_t(height_));
    for (int y = 0; y < height_; ++y) {
        std::vector<float> w(static_cast<std::size_t>(width_));
        double row = 0;
        for (int x = 0; x < width_; ++x) {
            w[std::size_t(x)] = luminance(&rgb_[3 * (std::size_t(y) * std::size_t(width_) + std::size_t(x))]);
            row += double(w[std::size_t(x)]);
        }
        const float sin_theta = std::sin((float(y) + 0.5f) * kPi / float(height_));
        rows[std::size_t(y)] = float(row / double(width_)) * sin_theta;
        // A black row is never chosen by the marginal; any conditional will do.
        if (!(row > 0)) std::fill(w.begin(), w.end(), 1.0f);
        conditional_.emplace_back(std::move(w));
    }
    double total = 0;
    for (float r : rows) total += double(r);
    if (!(total > 0))
        throw std::invalid_argument("--env " + map.name + ": the map is black (no pixel has a positive luminance)" +
                                    (intensity > 0 ? "" : "; --env-intensity is 0"));
    marginal_ = Distribution1D(std::move(rows));
}

glm::vec2 Environment::to_map(const glm::vec3& d) const {
    float u = (azimuth(d) - rotate_) / (2 * kPi);
    u -= std::floor(u);
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
    return {u, v};
}

glm::vec3 Environment::from_map(const glm::vec2& uv) const {
    const float phi = 2 * kPi * uv.x + rotate_, theta = kPi * uv.y;
    const float s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), s * std::cos(phi)};
}

std::size_t Environment::pixel(const glm::vec2& uv) const {
    const int x = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
    const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
    return std::size_t(y) * std::size_t(width_) + std::size_t(x);
}

glm::vec3 Environment::radiance(const glm::vec3& dir) const {
    if (constant()) return constant_;
    const float* p = &rgb_[3 * pixel(to_map(dir))];
    return {p[0], p[1], p[2]};
}

float Environment::pdf(const glm::vec3& dir) const {
    if (constant()) return 1.0f / (4 * kPi);
    const glm::vec2 uv = to_map(dir);
    const float sin_theta = std::sqrt(std::max(0.0f, 1 - dir.y * dir.y));
    // dω = 2π² sin θ du dv; at the poles the density in (u, v) is finite and the
    // direction's is unbounded but never sampled (sin θ = 0 has measure zero).
    if (!(sin_theta > 0)) return 0.0f;
    const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
    const int x = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
    const float p_uv = marginal_.pdf(y) * conditional_[std::size_t(y)].pdf(x);
    return p_uv / (2 * kPi * kPi * sin_theta);
}

Environment::Sample Environment::sample(float u1, float u2) const {
    Sample s;
    if (constant()) {
        s.wi = uniform_sphere(u1, u2);
        s.Le = constant_;
        s.pdf = 1.0f / (4 * kPi);
        return s;
    }
    const Distribution1D::Sample row = marginal_.sample(u2);
    const Distribution1D::Sample col = conditional_[std::size_t(row.bin)].sample(u1);
    const glm::vec2 uv(col.x, row.x);
    const float sin_theta = std::sin(kPi * uv.y);
    if (!(sin_theta > 0)) return s;
    s.wi = from_map(uv);
    const float* p = &rgb_[3 * (std::size_t(row.bin) * std::size_t(width_) + std::size_t(col.bin))];
    s.Le = {p[0], p[1], p[2]};
    s.pdf = row.pdf * col.pdf / (2 * kPi * kPi * sin_theta);
    return s;
}

}  // namespace render
