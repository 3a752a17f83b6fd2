#include "image_io.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "state_io.h"

namespace lava {

void writePng(const std::string& path, uint32_t width, uint32_t height,
              const std::vector<uint8_t>& rgba) {
  std::string png;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  stbi_write_png_to_func(append, &png, int(width), int(height), 4, rgba.data(), int(width * 4));
  writeFileAtomically(path, png);
}

}  // namespace lava
