// `lava demo`: the interactive window. Until the renderer lands (issue 3) it runs the
// default scene headless on the GPU and says what is missing.
#include <cstdio>
#include <optional>

#include "commands.h"
#include "gpu_simulator.h"
#include "options.h"
#include "runtime.h"

namespace lava::app {
namespace {

class DemoCommand final : public Command {
 public:
  explicit DemoCommand(CLI::App& app)
      : Command(app.add_subcommand("demo", "the interactive lava demo (window: issue 3)")),
        options_(*command_) {
    options_.addSceneFlags(scene_, device_);
  }

  int run() override {
    options_.resolve();
    Context context(contextOptions(device_));
    GpuSimulator simulator(context, scene_);
    const uint64_t steps = static_cast<uint64_t>(5.0 / double(scene_.dt));
    simulator.advance(steps);
    uint64_t alive = 0;
    for (const Particle& p : simulator.state().particles) alive += p.posAge.w >= 0.0f;
    std::printf("demo: simulated 5 s of the lava crater on %s (%llu particles alive).\n"
                "demo: the window and line renderer are not built yet (issue 3); meanwhile "
                "'lava simulate --out state.npy' and 'lava validate' work.\n",
                context.properties().deviceName, static_cast<unsigned long long>(alive));
    return finish(context, 0);
  }

 private:
  Options options_;
  Scene scene_;
  std::optional<unsigned> device_;
};

}  // namespace

std::unique_ptr<Command> makeDemo(CLI::App& app) { return std::make_unique<DemoCommand>(app); }

}  // namespace lava::app
