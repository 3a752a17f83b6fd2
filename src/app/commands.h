// The subcommands of `lava`. Each registers its flags on construction and runs when chosen.
#pragma once
#include <CLI/CLI.hpp>

#include <memory>

namespace lava::app {

class Command {
 public:
  virtual ~Command() = default;
  bool chosen() const { return command_->parsed(); }
  virtual int run() = 0;  // exit status; throws UsageError / ResourceError / VulkanError

 protected:
  explicit Command(CLI::App* command) : command_(command) {}
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
