// `lava`: the command line. Exit status 0 success, 1 a check failed or a resource ran out,
// 2 bad usage or bad input (one line naming the flag and what it accepts).
#include <unistd.h>

#include <csignal>

#include "cli.h"
#include "host/output.h"

namespace {

// Ctrl-C (or SIGTERM) in a command that does not take it itself (simulate --checkpoint
// does): end the progress line, say so, exit 130 (143). Output files appear whole or not at
// all (they are renamed into place); a temporary being written is removed.
extern "C" void onInterrupt(int signal) {
  lava::host::removePendingTemporary();
  static const char message[] = "\r\033[K\nlava: interrupted\n";
  const ssize_t written = write(STDERR_FILENO, message, sizeof(message) - 1);
  (void)written;
  _exit(signal == SIGINT ? 130 : 143);
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  return lava::app::runCommandLine(argc, argv);
}
