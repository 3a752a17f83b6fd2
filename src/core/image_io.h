// PNG output of rendered frames (stb_image_write), written whole or not at all.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace lava {

void writePng(const std::string& path, uint32_t width, uint32_t height,
              const std::vector<uint8_t>& rgba);

}  // namespace lava
