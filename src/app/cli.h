// The command line as a function: `lava`'s main() and the fuzz target of its arguments.
#pragma once

namespace lava::app {

// Parses argv, runs the command it names and returns the exit status: 0 success, 1 a
// check failed or a resource ran out, 2 bad usage or bad input (one line on stderr).
// `parseOnly`: stop once the command's flags and scene file are resolved and checked,
// before any device is made or output written (returning 0 there).
int runCommandLine(int argc, char** argv, bool parseOnly = false);

// Thrown by Options::resolve() in parseOnly mode; runCommandLine() catches it.
struct ParsedOnly {};
bool& parseOnlyMode();

}  // namespace lava::app
