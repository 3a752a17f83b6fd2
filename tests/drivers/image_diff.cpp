// Compares two frames of the same size (PNG): how many pixels differ, and by how much.
//
//   lava_image_diff A.png B.png MAX_PIXELS [LEVELS [MASK.png]]
//
// A pixel differs when a channel differs by more than LEVELS (default 0). Exit 0 when at
// most MAX_PIXELS pixels differ, 1 when more, 2 on bad input. MASK.png: the differing
// pixels white, the rest a dim copy of A.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#include <vector>

namespace {

struct Image {
  int width = 0, height = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> pixels{nullptr, stbi_image_free};
};

bool load(const char* path, Image& image) {
  int channels = 0;
  image.pixels.reset(stbi_load(path, &image.width, &image.height, &channels, 4));
  if (!image.pixels) std::fprintf(stderr, "image_diff: cannot read %s\n", path);
  return image.pixels != nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 6) {
    std::fprintf(stderr, "usage: lava_image_diff A.png B.png MAX_PIXELS [LEVELS [MASK.png]]\n");
    return 2;
  }
  Image a, b;
  if (!load(argv[1], a) || !load(argv[2], b)) return 2;
  if (a.width != b.width || a.height != b.height) {
    std::fprintf(stderr, "image_diff: %dx%d against %dx%d\n", a.width, a.height, b.width, b.height);
    return 2;
  }
  const long allowed = std::strtol(argv[3], nullptr, 10);
  const int levels = argc > 4 ? std::atoi(argv[4]) : 0;
  long differ = 0, lit = 0;
  int largest = 0;
  const long pixels = long(a.width) * a.height;
  std::vector<unsigned char> mask(size_t(pixels) * 3);
  for (long i = 0; i < pixels; ++i) {
    const unsigned char* p = a.pixels.get() + 4 * i;
    const unsigned char* q = b.pixels.get() + 4 * i;
    int most = 0;
    for (int k = 0; k < 3; ++k) most = std::max(most, std::abs(int(p[k]) - int(q[k])));
    differ += most > levels;
    largest = std::max(largest, most);
    lit += p[0] > 128;
    for (int k = 0; k < 3; ++k) mask[3 * i + k] = most > levels ? 255 : p[k] / 4;
  }
  std::printf(
      "%ld of %ld pixels differ by more than %d (largest channel difference %d; %ld "
      "pixels lit in the first)\n",
      differ, pixels, levels, largest, lit);
  if (argc > 5 && !stbi_write_png(argv[5], a.width, a.height, 3, mask.data(), a.width * 3)) {
    std::fprintf(stderr, "image_diff: cannot write %s\n", argv[5]);
    return 2;
  }
  return differ <= allowed ? 0 : 1;
}
