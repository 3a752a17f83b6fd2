// The scene keys as data: each key's name, kind, help, range and the field it sets. One
// table serves setSceneKey() (text in), checkScene() (ranges of a Scene built in code) and
// toToml() (text out), so a range is written once.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "lava/scene.h"
#include "lava/scene_keys.h"

namespace lava::detail {

struct KeyDef {
  SceneKey key;
  // Parses `text` into the field of table entry `where`; `parameter` names it in errors.
  std::function<void(Scene&, size_t where, const std::string& parameter, const std::string& text)>
      set;
  // Throws InvalidArgument naming `parameter` unless the field's value is in range.
  std::function<void(const Scene&, size_t where, const std::string& parameter)> check;
  // The field's value as text that set() reads back exactly.
  std::function<std::string(const Scene&, size_t where)> text;
  bool emitterZero = false;  // a top-level key that sets emitter 0 (flat, format 1 files)
  bool flowOnly = false;     // an emitter key that only scenes with a flow write out
};

// A flow emitter's mass when its table gives none: density (radius / 2)^3, particles spaced
// half the radius apart.
float defaultFlowMass(const Flow& flow);

const std::vector<KeyDef>& keyDefs(KeyTable table);
// The definition of `key` in `table`, or null.
const KeyDef* findKey(KeyTable table, const std::string& key);
// "particles, rate, ..." for messages.
std::string keyList(KeyTable table);
// "unknown key; did you mean <nearest>? (accepted: <extra><keys>)" for a key not in `table`.
std::string unknownKey(KeyTable table, const std::string& key, const std::string& extra = "");

// Shortest text that reads back as exactly this float / double.
std::string formatFloat(float value);
std::string formatDouble(double value);

}  // namespace lava::detail
