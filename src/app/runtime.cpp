#include "runtime.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "host/output.h"
#include "host/vulkan.h"
#include "paths.h"

namespace lava::app {

bool validationRequested() {
  const char* validation = std::getenv("LAVA_VALIDATION");
  return validation && *validation && std::strcmp(validation, "0") != 0;
}

namespace {
const char* source = "--device";
}

const char* deviceSource() {
  return source;
}

DeviceOptions deviceOptions(std::optional<unsigned> device) {
  DeviceOptions options;
  source = "--device";
  options.validation = validationRequested();
  options.index = device;
  if (const char* profile = std::getenv("LAVA_DEVICE_PROFILE");
      profile && !host::applyDeviceProfile(options, profile))
    throw UsageError(std::string("LAVA_DEVICE_PROFILE: expected ") + host::kDeviceProfiles +
                           ", got '" + profile + "'");
  if (!device)
    if (const char* env = std::getenv("LAVA_DEVICE"); env && *env) {
      char* end = nullptr;
      errno = 0;
      const unsigned long value = std::strtoul(env, &end, 10);
      if (*end != '\0' || errno != 0 || env[0] == '-' || value > 255)
        throw UsageError(std::string("LAVA_DEVICE: expected a device index from 'lava info', "
                                           "got '") +
                               env + "'");
      options.index = static_cast<unsigned>(value);
      source = "LAVA_DEVICE";
    }
  return options;
}

int finish(Device& device, int status) {
  device.waitIdle();  // a device lost at the end is an error too (VulkanError: exit 1)
  const auto messages = device.takeValidationMessages();
  for (const std::string& m : messages) std::fprintf(stderr, "lava: validation: %s\n", m.c_str());
  return messages.empty() ? status : 1;
}

Progress::Progress(std::string label, uint64_t total)
    : label_(std::move(label)),
      total_(total),
      terminal_(isatty(STDOUT_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(uint64_t done) {
  if (!terminal_ || total_ == 0) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char eta[48] = "";
  if (done > 0 && done < total_ && elapsed > 0.5)
    std::snprintf(eta, sizeof(eta), ", %.0f s left",
                  elapsed * double(total_ - done) / double(done) + 0.5);
  std::printf("\r\033[K%s %llu/%llu (%.0f%%%s)", label_.c_str(),
              static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_),
              100.0 * double(done) / double(total_), eta);
  std::fflush(stdout);
  shown_ = true;
}

void Progress::clear() {
  if (shown_) std::printf("\r\033[K");
  shown_ = false;
}

Progress::~Progress() {
  clear();
}

std::string formatSeconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f s", seconds);
  return text;
}

}  // namespace lava::app
