// Scene files, format 1 and 2, as every reader takes them (parseScene, then checkScene for
// what no single key decides: the program after its flags, the simulations): text to a valid
// Scene or InvalidArgument, never a crash. An accepted scene's format-2 TOML reads back into
// the same scene, valid again: writing it once more gives the same text.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "lava/error.h"
#include "lava/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  lava::Scene scene;
  try {
    scene = lava::parseScene(text, "fuzz.toml");
    lava::checkScene(scene);
  } catch (const lava::InvalidArgument&) {
    return 0;  // refused, with a message naming the key
  }
  const std::string written = lava::toToml(scene);
  const lava::Scene again = lava::parseScene(written, "written.toml");
  lava::checkScene(again);  // throws, and so fails, if what was written is not valid
  if (lava::toToml(again) != written) std::abort();
  return 0;
}
