// Scene files: TOML in (format 2 tables or the flat format 1 keys), TOML out.
// toml++ compiled into Lava (header-only mode): no run-time dependency for its users.
#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include <fstream>
#include <sstream>

#include "common/files.h"
#include "common/toml_text.h"
#include "keys.h"
#include "lava/error.h"
#include "lava/scene.h"
#include "lava/scene_keys.h"

namespace lava {
namespace {

using detail::findKey;
using detail::keyList;

std::string typeName(const toml::node& node) {
  std::ostringstream type;
  type << node.type();
  return type.str();
}

// A TOML value as the text setSceneKey() reads: numbers exactly, arrays joined by commas.
std::string valueText(const std::string& parameter, const toml::node& node) {
  if (auto i = node.as_integer()) return std::to_string(i->get());
  if (auto f = node.as_floating_point()) return detail::formatDouble(f->get());
  if (auto s = node.as_string()) return s->get();
  if (auto b = node.as_boolean()) return b->get() ? "true" : "false";
  if (auto array = node.as_array()) {
    std::string joined;
    for (const toml::node& element : *array) {
      if (element.is_array() || element.is_table())
        throw InvalidArgument(parameter,
                              "expected an array of numbers, got a nested " + typeName(element));
      joined += (joined.empty() ? "" : ",") + valueText(parameter, element);
    }
    return joined;
  }
  throw InvalidArgument(parameter, "expected a value, got a TOML " + typeName(node));
}

// Booleans are not numbers: only a flag takes one, and a flag takes nothing else.
std::string keyText(const std::string& parameter, const toml::node& node, KeyKind kind) {
  if (kind == KeyKind::Flag) {
    if (!node.is_boolean())
      throw InvalidArgument(parameter, "expected true or false, got a TOML " + typeName(node));
    return valueText(parameter, node);
  }
  if (node.is_boolean() && kind != KeyKind::Name)
    throw InvalidArgument(parameter, "expected a number, got a TOML boolean");
  if (node.is_string() && kind != KeyKind::Name)
    throw InvalidArgument(parameter, "expected a number, got a TOML string");
  if (kind == KeyKind::Vector && !node.is_array())
    throw InvalidArgument(parameter, "expected an array of 3 numbers like [0, 1.5, 0]");
  if (kind != KeyKind::Vector && node.is_array())
    throw InvalidArgument(parameter, "expected one value, got an array");
  if (kind == KeyKind::Name && !node.is_string())
    throw InvalidArgument(parameter, "expected a name in quotes, got a TOML " + typeName(node));
  return valueText(parameter, node);
}

// Reads the [[table]] entries `array` into rows `index` of the scene's list for `table`.
void readTables(Scene& scene, const std::string& file, const char* prefix, KeyTable table,
                const toml::array& array) {
  for (size_t i = 0; i < array.size(); ++i) {
    const std::string at = file + ": " + prefix + "[" + std::to_string(i) + "]";
    const toml::table* entries = array[i].as_table();
    if (!entries) throw InvalidArgument(at, "expected a table");
    for (const auto& [key, node] : *entries) {
      const std::string name(key.str()), parameter = at + "." + name;
      const detail::KeyDef* def = findKey(table, name);
      if (!def) throw InvalidArgument(parameter, detail::unknownKey(table, name));
      def->set(scene, i, parameter, keyText(parameter, node, def->key.kind));
    }
  }
}

// The [flow] table; a flow emitter in a file without one gets the flow's defaults, and one
// without `mass` particles spaced half the radius apart.
void readFlow(Scene& scene, const std::string& file, const toml::table& root) {
  if (const toml::node* node = root.get("flow")) {
    const std::string at = file + ": flow";
    const toml::table* entries = node->as_table();
    if (!entries) throw InvalidArgument(at, "expected a [flow] table");
    scene.flow.emplace();
    for (const auto& [key, value] : *entries) {
      const std::string name(key.str()), parameter = at + "." + name;
      const detail::KeyDef* def = findKey(KeyTable::Flow, name);
      if (!def) throw InvalidArgument(parameter, detail::unknownKey(KeyTable::Flow, name));
      def->set(scene, 0, parameter, keyText(parameter, value, def->key.kind));
    }
  }
  if (!scene.flows()) return;
  if (!scene.flow) scene.flow.emplace();
  const toml::array* emitters = root.get("emitter") ? root.get("emitter")->as_array() : nullptr;
  for (size_t k = 0; k < scene.emitters.size(); ++k) {
    const toml::table* entries =
        emitters && k < emitters->size() ? (*emitters)[k].as_table() : nullptr;
    if (scene.emitters[k].flow && entries && !entries->contains("mass"))
      scene.emitters[k].mass = detail::defaultFlowMass(*scene.flow);
  }
}

// The file's TOML, or an InvalidArgument at the line and column where it stops being TOML.
toml::table parseToml(const std::string& text, const std::string& file) {
  toml::table root;
  try {
    root = toml::parse(common::asciiForToml(text), file);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    const std::string at = std::to_string(where.line) + ":" + std::to_string(where.column);
    if (common::errorIsNonAscii(text, where.line, where.column, e.description()))
      throw InvalidArgument(file, at + ": a character outside ASCII (only comments may hold one)");
    throw InvalidArgument(file, at + ": not valid TOML (" + std::string(e.description()) + ")");
  }
  return root;
}

// Reads the [[emitter]], [[force]] and [[collider]] tables; true when the file has emitter
// tables (so the flat files' emitter-0 keys may not be used).
bool readListTables(Scene& scene, const std::string& file, const toml::table& root) {
  const char* tables[] = {"emitter", "force", "collider"};  // [flow] is read last
  const uint32_t most[] = {kMaxEmitters, kMaxForces, kMaxColliders};
  const KeyTable kinds[] = {KeyTable::Emitter, KeyTable::Force, KeyTable::Collider};
  scene.forces.clear();
  scene.colliders.clear();
  bool emitterTables = false;
  for (int t = 0; t < 3; ++t) {
    const toml::node* node = root.get(tables[t]);
    if (!node) continue;
    // `emitter = [x, y, z]` is the flat files' emitter-0 position, not a table.
    if (t == 0 && !node->is_array_of_tables() && !node->is_table()) continue;
    const std::string parameter = file + ": " + tables[t];
    const toml::array* array = node->as_array();
    if (!array || !array->is_array_of_tables())
      throw InvalidArgument(parameter, std::string("expected [[") + tables[t] + "]] tables");
    if (array->size() > most[t])
      throw InvalidArgument(parameter, "at most " + std::to_string(most[t]) + " [[" + tables[t] +
                                           "]] tables, got " + std::to_string(array->size()));
    if (t == 0) {
      if (array->empty()) throw InvalidArgument(parameter, "a scene needs at least one emitter");
      scene.emitters.assign(array->size(), Emitter{});
      emitterTables = true;
    } else if (t == 1) {
      scene.forces.assign(array->size(), Force{});
    } else {
      scene.colliders.assign(array->size(), Collider{});
    }
    readTables(scene, file, tables[t], kinds[t], *array);
  }
  return emitterTables;
}

// Reads the top-level keys (format, the scene's own, format 1's emitter-0 ones), in file
// order; a key Lava does not know goes to `other`, if given, before it is an error.
void readTopKeys(Scene& scene, const std::string& file, const toml::table& root,
                 bool emitterTables, const OtherKey& other) {
  for (const auto& [key, node] : root) {
    const std::string name(key.str()), parameter = file + ": " + name;
    if ((name == "emitter" && emitterTables) || name == "force" || name == "collider" ||
        name == "flow")
      continue;
    if (name == "format") {
      const auto format = node.as_integer();
      if (!format || (format->get() != 1 && format->get() != 2))
        throw InvalidArgument(parameter, "expected 1 or 2");
      continue;
    }
    const detail::KeyDef* def = findKey(KeyTable::Top, name);
    if (!def) {
      if (other && other(name, valueText(parameter, node))) continue;
      throw InvalidArgument(parameter, detail::unknownKey(KeyTable::Top, name, "format, ") +
                                           " or the tables [[emitter]], [[force]], [[collider]], [flow]");
    }
    if (def->emitterZero && emitterTables)
      throw InvalidArgument(parameter, "set it in an [[emitter]] table (this file has them)");
    def->set(scene, 0, parameter, keyText(parameter, node, def->key.kind));
  }
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& file, const OtherKey& other) {
  const toml::table root = parseToml(text, file);
  Scene scene;
  const bool emitterTables = readListTables(scene, file, root);
  readTopKeys(scene, file, root, emitterTables, other);
  readFlow(scene, file, root);
  return scene;
}

Scene loadScene(const std::string& path, const OtherKey& other) {
  return parseScene(common::readWholeFile(path, "a scene file"), path, other);
}

std::string toToml(const Scene& scene) {
  checkScene(scene);
  std::ostringstream out;
  auto line = [&out](const detail::KeyDef& d, const Scene& s, size_t i) {
    const std::string text = d.text(s, i);
    out << d.key.name << " = ";
    if (d.key.kind == KeyKind::Vector)
      out << "[" << text << "]\n";
    else if (d.key.kind == KeyKind::Name)  // flags, numbers: as they are
      out << "\"" << text << "\"\n";
    else
      out << text << "\n";
  };
  out << "format = 2\n";
  for (const detail::KeyDef& d : detail::keyDefs(KeyTable::Top))
    if (!d.emitterZero) line(d, scene, 0);
  const std::pair<const char*, KeyTable> tables[] = {
      {"emitter", KeyTable::Emitter}, {"force", KeyTable::Force}, {"collider", KeyTable::Collider}};
  const size_t counts[] = {scene.emitters.size(), scene.forces.size(), scene.colliders.size()};
  for (int t = 0; t < 3; ++t)
    for (size_t i = 0; i < counts[t]; ++i) {
      out << "\n[[" << tables[t].first << "]]\n";
      for (const detail::KeyDef& d : detail::keyDefs(tables[t].second))
        if (scene.flow || !d.flowOnly) line(d, scene, i);  // scenes without a flow: as before
    }
  if (scene.flow) {
    out << "\n[flow]\n";
    for (const detail::KeyDef& d : detail::keyDefs(KeyTable::Flow)) line(d, scene, 0);
  }
  return out.str();
}

}  // namespace lava
