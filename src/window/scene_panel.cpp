#include "scene_panel.h"

#include <imgui.h>

#include <cstdio>
#include <fstream>

#include "host/output.h"
#include "lava/error.h"

namespace lava::window {
namespace {

// Each editor writes its value back only when the user changed it (no clamping, no
// rounding of what was loaded).
bool edit(const char* label, float& value, float speed = 0.01f) {
  float v = value;
  if (!ImGui::DragFloat(label, &v, speed, 0.0f, 0.0f, "%.6g")) return false;
  value = v;
  return true;
}

bool edit(const char* label, double& value, double speed) {
  double v = value;
  if (!ImGui::DragScalar(label, ImGuiDataType_Double, &v, float(speed), nullptr, nullptr, "%.9g"))
    return false;
  value = v;
  return true;
}

bool edit(const char* label, uint32_t& value, float speed = 1.0f) {
  uint32_t v = value;
  if (!ImGui::DragScalar(label, ImGuiDataType_U32, &v, speed, nullptr, nullptr, "%u")) return false;
  value = v;
  return true;
}

bool edit(const char* label, Vec3& value, float speed = 0.01f) {
  float v[3] = {value.x, value.y, value.z};
  if (!ImGui::DragFloat3(label, v, speed, 0.0f, 0.0f, "%.5g")) return false;
  value = {v[0], v[1], v[2]};
  return true;
}

template <typename E>
bool choose(const char* label, E& value, int count) {
  bool changed = false;
  if (ImGui::BeginCombo(label, name(value))) {
    for (int i = 0; i < count; ++i) {
      const bool selected = value == E(i);
      if (ImGui::Selectable(name(E(i)), selected)) {
        changed = value != E(i);
        value = E(i);
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

// A list's editor: each item in a tree node titled "<noun> i (<its kind>)" with `fields`
// editing it, a remove button while more than `least` remain, and an add button (`added()`)
// while fewer than `most`. IDs from `id` up, so that lists do not clash.
template <typename Item, typename Kind, typename Fields, typename Added>
bool editList(std::vector<Item>& items, int id, const std::string& noun, size_t least, size_t most,
              const Kind& kind, const Fields& fields, const Added& added) {
  bool changed = false;
  for (size_t i = 0; i < items.size(); ++i) {
    ImGui::PushID(id + int(i));
    const std::string title = noun + " " + std::to_string(i) + " (" + kind(items[i]) + ")";
    if (ImGui::TreeNode(title.c_str())) {
      changed |= fields(items[i]);
      if (items.size() > least && ImGui::SmallButton(("remove " + noun).c_str())) {
        items.erase(items.begin() + long(i));
        changed = true;
        ImGui::TreePop();
        ImGui::PopID();
        break;
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (items.size() < most && ImGui::SmallButton(("add " + noun).c_str())) {
    items.push_back(added());
    changed = true;
  }
  return changed;
}

}  // namespace

bool sameStructure(const Scene& a, const Scene& b) {
  if (a.emitters.size() != b.emitters.size() || a.flow.has_value() != b.flow.has_value())
    return false;
  for (size_t k = 0; k < a.emitters.size(); ++k)
    if (a.emitters[k].particles != b.emitters[k].particles ||
        a.emitters[k].flow != b.emitters[k].flow)
      return false;
  return true;
}

bool ScenePanel::emitters() {
  const auto fields = [&](Emitter& e) {
    bool changed = false;
    changed |= edit("particles", e.particles, 64.0f);
    changed |= edit("rate (1/s)", e.rate, 10.0);
    changed |= edit("burst", e.burst, 10.0f);
    changed |= edit("burst interval (s)", e.burstInterval, 0.01);
    changed |= choose("shape", e.shape, 4);
    changed |= edit("position (m)", e.position);
    if (e.shape == Shape::Disc || e.shape == Shape::Sphere) changed |= edit("radius (m)", e.radius);
    if (e.shape == Shape::Box) changed |= edit("half-extents (m)", e.size);
    changed |= edit("velocity (m/s)", e.velocity, 0.05f);
    changed |= edit("spread (m/s)", e.spread, 0.02f);
    changed |= edit("mass (kg)", e.mass);
    changed |= edit("lifetime (s)", e.lifetime);
    if (ImGui::Checkbox("flow (molten rock)", &e.flow)) {
      changed = true;
      if (e.flow && !edited_.flow) edited_.flow.emplace();
      if (e.flow) {  // a flow particle's mass at the rest spacing, radius / 2
        const float spacing = 0.5f * edited_.flow->radius;
        e.mass = edited_.flow->density * spacing * spacing * spacing;
      }
    }
    if (e.flow) changed |= edit("temperature (K, 0: the flow's)", e.temperature, 1.0f);
    return changed;
  };
  return editList(
      edited_.emitters, 0, "emitter", 1, kMaxEmitters,
      [](const Emitter& e) { return name(e.shape); }, fields,
      [&] { return Emitter(edited_.emitters.back()); });
}

bool ScenePanel::forces() {
  const auto fields = [](Force& f) {
    bool changed = choose("type", f.type, 2);
    changed |= edit("position (m)", f.position);
    if (f.type == ForceType::Vortex) changed |= edit("axis", f.axis);
    changed |= edit("strength", f.strength);
    if (f.type == ForceType::Attractor) changed |= edit("radius (m, 0: all)", f.radius);
    return changed;
  };
  return editList(
      edited_.forces, 100, "force", 0, kMaxForces, [](const Force& f) { return name(f.type); },
      fields, [] { return Force{}; });
}

bool ScenePanel::flow() {
  if (!edited_.flow) {
    if (!ImGui::SmallButton("add a flow")) return false;
    edited_.flow.emplace();
    return true;
  }
  Flow& f = *edited_.flow;
  bool changed = false;
  changed |= edit("radius (m)", f.radius, 0.001f);
  changed |= edit("density (kg/m3)", f.density, 10.0f);
  changed |= edit("temperature (K)", f.temperature, 1.0f);
  changed |= edit("viscosity (m2/s)", f.viscosity, 0.001f);
  changed |= edit("viscosity at the solidus (m2/s)", f.viscositySolidus, 0.01f);
  changed |= edit("solidus (K)", f.solidus, 1.0f);
  changed |= edit("ambient (K)", f.ambient, 1.0f);
  changed |= edit("cooling in the air (1/s)", f.coolingAir, 0.001f);
  changed |= edit("cooling on the ground (1/s)", f.coolingGround, 0.01f);
  changed |= edit("conduction (m2/s)", f.conduction, 0.0001f);
  changed |= edit("sound speed (m/s)", f.soundSpeed, 0.1f);
  changed |= edit("restitution", f.restitution);
  if (ImGui::SmallButton("remove the flow")) {
    edited_.flow.reset();
    for (Emitter& e : edited_.emitters) e.flow = false;
    changed = true;
  }
  return changed;
}

bool ScenePanel::colliders() {
  const auto fields = [](Collider& c) {
    bool changed = false;
    changed |= choose("type", c.type, 4);
    changed |= edit("position (m)", c.position);
    switch (c.type) {
      case ColliderType::Plane:
        changed |= edit("normal", c.normal);
        break;
      case ColliderType::Sphere:
        changed |= edit("radius (m)", c.radius);
        break;
      case ColliderType::Box:
        changed |= edit("half-extents (m)", c.size);
        break;
      case ColliderType::Cone:
        changed |= edit("base radius (m)", c.baseRadius);
        changed |= edit("top radius (m)", c.topRadius);
        changed |= edit("height (m)", c.height);
        break;
    }
    changed |= edit("restitution", c.restitution);
    changed |= edit("friction (kept)", c.friction);
    return changed;
  };
  return editList(
      edited_.colliders, 200, "collider", 0, kMaxColliders,
      [](const Collider& c) { return name(c.type); }, fields, [] { return Collider{}; });
}

ScenePanel::Change ScenePanel::draw(const Scene& running) {
  bool changed = false;
  changed |= edit("dt (s)", edited_.dt, 0.00001);
  changed |= edit("gravity (m/s2)", edited_.gravity, 0.05f);
  changed |= edit("ground restitution", edited_.restitution);
  changed |= edit("ground friction (kept)", edited_.friction);
  changed |= edit("wind (N)", edited_.wind, 0.05f);
  changed |= edit("drag (N s/m)", edited_.drag);
  changed |= edit("seed", edited_.seed);
  changed |= edit("line scale (s)", edited_.lineScale, 0.001f);
  changed |= choose("integrator", edited_.integrator, 3);
  // A tree node of the panel: its editor runs while it is open.
  const auto section = [](const char* title, const auto& editor) {
    if (!ImGui::TreeNode(title)) return false;
    const bool edited = editor();
    ImGui::TreePop();
    return edited;
  };
  changed |= section("emitters", [this] { return emitters(); });
  changed |= section("forces", [this] { return forces(); });
  changed |= section("colliders", [this] { return colliders(); });
  changed |= section("flow", [this] { return flow(); });
  char path[512];
  std::snprintf(path, sizeof(path), "%s", path_.c_str());
  if (ImGui::InputText("file", path, sizeof(path))) path_ = path;
  bool loaded = false;
  if (ImGui::Button("load")) {
    try {
      edited_ = loadScene(path_);
      message_ = "loaded " + path_;
      loaded = true;
    } catch (const Error& e) {
      message_ = e.what();
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("save")) {
    try {
      host::writeFileAtomically(path_, toToml(edited_));
      message_ = "saved " + path_;
    } catch (const std::exception& e) {
      message_ = e.what();
    }
  }
  if (!message_.empty()) ImGui::TextWrapped("%s", message_.c_str());
  if (!changed && !loaded) return Change::None;
  return sameStructure(edited_, running) ? Change::Live : Change::Structure;
}

}  // namespace lava::window
