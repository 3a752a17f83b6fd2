#include "runtime.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace lava::app {

ContextOptions contextOptions(std::optional<unsigned> device) {
  ContextOptions options;
  const char* validation = std::getenv("LAVA_VALIDATION");
  options.validation = validation && *validation && std::strcmp(validation, "0") != 0;
  options.syncValidation = options.validation;
  options.deviceIndex = device;
  return options;
}

int finish(Context& context, int status) {
  const auto messages = context.takeValidationMessages();
  for (const std::string& m : messages) std::fprintf(stderr, "lava: validation: %s\n", m.c_str());
  return messages.empty() ? status : 1;
}

Progress::Progress(std::string label, uint64_t total)
    : label_(std::move(label)), total_(total), terminal_(isatty(STDOUT_FILENO) == 1) {}

void Progress::update(uint64_t done) {
  if (!terminal_ || total_ == 0) return;
  std::printf("\r%s %llu/%llu (%.0f%%)", label_.c_str(), static_cast<unsigned long long>(done),
              static_cast<unsigned long long>(total_), 100.0 * double(done) / double(total_));
  std::fflush(stdout);
  shown_ = true;
}

Progress::~Progress() {
  if (shown_) std::printf("\r\033[K");
}

std::string formatSeconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f s", seconds);
  return text;
}

}  // namespace lava::app
