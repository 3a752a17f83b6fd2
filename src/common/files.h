// Files that appear whole or not at all, written the same way by the library (checkpoints)
// and the program (states, frames, reports).
#pragma once
#include <string>

namespace lava::common {

// Writes `contents` into a temporary of its own beside `path` (`path`.XXXXXX, so that
// concurrent writers never share one), gives it the permissions a new file gets under the
// process's umask, flushes it to the disk (fsync) and renames it into place; interrupted
// writes (EINTR) are retried. On failure the temporary is removed and a lava::ResourceError
// says "cannot write '<path>': <reason>". `onTemporary`, when given, is called with the
// temporary's name as soon as it exists and with nullptr once it no longer does, so that a
// signal handler can remove it.
void writeFileAtomically(const std::string& path, const std::string& contents,
                         void (*onTemporary)(const char* temporary) = nullptr);

// A file another program wrote at `temporary` (beside `path`), flushed to the disk and renamed
// into place as writeFileAtomically() does; false when it cannot be (the temporary stays).
bool moveIntoPlace(const std::string& temporary, const std::string& path);

// The whole of the file at `path`. A folder, or a file that cannot be read, is a
// lava::InvalidArgument naming the path: "is a folder, not <what>" or "cannot read <what>:
// <reason>" (`what`: "a scene file", say).
std::string readWholeFile(const std::string& path, const std::string& what);

}  // namespace lava::common
