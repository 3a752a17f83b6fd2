// Suite files: text to cases or one UsageError naming the file, the case and the key, never
// a crash. Every accepted case's scene is valid (checkScene).
#include <cstddef>
#include <cstdint>
#include <string>

#include "lava/error.h"
#include "paths.h"
#include "suite.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Scene files a case names are looked for beside a suite that is not there.
    for (const lava::app::Case& c : lava::app::parseSuite(text, "/nonexistent/fuzz.toml"))
      lava::checkScene(c.scene);
  } catch (const lava::app::UsageError&) {
  }
  return 0;
}
