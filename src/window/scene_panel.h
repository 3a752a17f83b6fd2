// The demo panel's scene editor (Dear ImGui): every key of a Scene, the emitter, force and
// collider lists with add and remove, the integrator, loading and saving a scene file. A
// value changes only when the user edits it, so the panel shows and keeps exactly what the
// command line or the scene file set.
#pragma once
#include <string>

#include "lava/scene.h"

namespace lava::window {

class ScenePanel {
 public:
  explicit ScenePanel(const Scene& scene) : edited_(scene) {}

  enum class Change {
    None,       // nothing edited this frame
    Live,       // parameters a running simulation takes (same emitters and capacities)
    Structure,  // emitters, capacities or the flow's emitters changed: takes a restart
  };
  // Draws the editor inside the current ImGui window; says what the user changed.
  Change draw(const Scene& running);
  const Scene& edited() const { return edited_; }
  void reset(const Scene& scene) { edited_ = scene; }
  // The outcome of the last apply (an invalid value, a file that did not load), shown.
  void setMessage(std::string message) { message_ = std::move(message); }

 private:
  bool emitters();
  bool forces();
  bool colliders();
  bool flow();

  Scene edited_;
  std::string path_ = "scene.toml";
  std::string message_;
};

// Whether `a` and `b` have the same emitters with the same capacities, the same flow
// emitters, and both a flow or neither (a running simulation can switch between them).
bool sameStructure(const Scene& a, const Scene& b);

}  // namespace lava::window
