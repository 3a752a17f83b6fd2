// The subcommands of `lava`. Each registers its flags on construction and runs when chosen.
#pragma once
#include <memory>

// CLI11 is confined to cli.cpp and options.cpp: its header alone costs a translation unit
// 16 s under the sanitizers (docs/testing.md, "Build time").
namespace CLI {
class App;
}

namespace lava::app {

class Command {
 public:
  virtual ~Command() = default;
  bool chosen() const;
  virtual int run() = 0;  // exit status; throws UsageError / ResourceError / VulkanError

 protected:
  // Registers the subcommand `name` on `app` (cli.cpp).
  Command(CLI::App& app, const char* name, const char* description);
  CLI::App* command_;
};

std::unique_ptr<Command> makeSimulate(CLI::App& app);
std::unique_ptr<Command> makeValidate(CLI::App& app);
std::unique_ptr<Command> makeInfo(CLI::App& app);
std::unique_ptr<Command> makeRender(CLI::App& app);
std::unique_ptr<Command> makeBench(CLI::App& app);
std::unique_ptr<Command> makeDemo(CLI::App& app);
std::unique_ptr<Command> makeStudy(CLI::App& app);

}  // namespace lava::app
