// lobe_explorer — OpenEXR and PNG output, through the examples' shared image code.
#include "image_io.hpp"

#include <common/image_io.hpp>

namespace lobe_explorer {

void write_exr(const std::string& path, const LinearImage& image,
               const std::vector<std::pair<std::string, std::string>>& attributes) {
    std::vector<float> rgb(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) rgb[3 * i + std::size_t(c)] = float(image.pixels[i][c]);
    hairscatter_examples::write_exr_rgb(path, image.width, image.height, rgb, attributes);
}

void write_png(const std::string& path, const Canvas& canvas) {
    hairscatter_examples::write_png_rgb8(path, canvas.width, canvas.height, canvas.rgb);
}

}  // namespace lobe_explorer
