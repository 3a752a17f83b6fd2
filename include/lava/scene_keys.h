// Scene keys as text: the names scene files, the `lava` program and Python use, each
// key's kind, help and default, setting one from text, and the "did you mean" of names.
// A tool header: <lava/lava.h> does not include it.
#pragma once
#include <string>
#include <vector>

#include "export.h"
#include "scene.h"

namespace lava {

// A value is text: a number ("0.45"), a vector ("0,1.5,0"), a name ("velocity-verlet"), or
// a flag ("true", "false").
// Top-level keys: dt gravity restitution friction wind drag seed line-scale integrator,
// and the emitter-0 keys particles rate emitter emitter-radius velocity spread mass burst
// burst-interval shape lifetime. Table keys are listed by sceneKeys().

enum class KeyKind { Integer, Number, Vector, Name, Flag };  // Flag: true or false

struct SceneKey {
  std::string name;  // "emitter-radius"
  KeyKind kind;
  std::string help;      // one line: meaning, unit, accepted range
  std::string fallback;  // the default, as text
};

enum class KeyTable { Top, Emitter, Force, Collider, Flow };

// The keys of a table (Top: top-level keys, emitter-0 keys included), in order.
LAVA_API const std::vector<SceneKey>& sceneKeys(KeyTable table);

// The name in `names` nearest to `given` ('_' read as '-'), at most `maxEdits` edits away
// (the first on a tie), or "": the "did you mean" of scene keys and of the program's flags.
LAVA_API std::string nearestName(const std::string& given, const std::vector<std::string>& names,
                                 size_t maxEdits);

// Sets one key from text; `where` is the table index (emitter, force or collider;
// ignored for Top and Flow; a Flow key gives a scene without one the flow's defaults first). Throws InvalidArgument naming the key on a bad value or an unknown
// key. Top-level emitter keys set emitter 0.
LAVA_API void setSceneKey(Scene& scene, KeyTable table, size_t where, const std::string& key,
                          const std::string& value);

}  // namespace lava
