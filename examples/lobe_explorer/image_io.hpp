// lobe_explorer — writing the images: OpenEXR (linear float RGB) and PNG (the preview).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "image.hpp"

namespace lobe_explorer {

// Writes R, G, B as 32-bit float (f has sharp peaks that can exceed half's 65504) with
// the given string attributes in the header. Throws std::runtime_error on failure.
void write_exr(const std::string& path, const LinearImage& image,
               const std::vector<std::pair<std::string, std::string>>& attributes);

// Throws std::runtime_error on failure.
void write_png(const std::string& path, const Canvas& canvas);

}  // namespace lobe_explorer
