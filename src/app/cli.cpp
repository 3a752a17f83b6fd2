#include "cli.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "host/output.h"
#include "lava/error.h"
#include "lava/scene.h"
#include "lava/scene_keys.h"
#include "lava/version.h"
#include "paths.h"
#include "runtime.h"

namespace {

// CLI11's messages, in the form every other usage error takes: the flag, then what is
// accepted. A repeated flag and a flag without its value are the two it words its own way.
// The flag of `command` nearest to `given` (a typo, `_` for `-`), or "".
std::string nearestFlag(const CLI::App& app, const char* command, const std::string& given) {
  std::vector<std::string> flags;
  for (const CLI::App* sub : app.get_subcommands({}))
    if (command && sub->get_name() == command)
      for (const CLI::Option* option : sub->get_options())
        for (const std::string& name : option->get_lnames()) flags.push_back("--" + name);
  return lava::nearestName(given, flags, 3);
}

std::string usageMessage(const CLI::App& app, const char* command, const CLI::ParseError& error) {
  const std::string what = error.what();
  static const std::regex unexpected(
      R"(^The following arguments? (?:was|were) not expected: (.*)$)");
  std::smatch u;
  std::string flag;
  if (std::regex_match(what, u, unexpected)) {
    std::istringstream words(u[1].str());
    for (std::string w; words >> w;)
      if (w.rfind("--", 0) == 0 && flag.empty()) flag = w;
  }
  if (!flag.empty()) {
    const std::string near = nearestFlag(app, command, flag);
    return flag + ": unknown flag" + (near.empty() ? "" : "; did you mean " + near + "?") +
           " (see 'lava " + (command ? command : "") + " --help')";
  }
  static const std::regex repeated(R"(^(-[-\w]+): At Most 1 required but received (\d+)$)");
  static const std::regex missing(R"(^(-[-\w]+): \d+ required \w+ missing$)");
  std::smatch m;
  if (std::regex_match(what, m, repeated))
    return m[1].str() + ": given " + m[2].str() + " times; give it once";
  if (std::regex_match(what, m, missing)) {
    std::string accepted;
    for (const CLI::App* sub : app.get_subcommands({}))
      if (command && sub->get_name() == command)
        if (const CLI::Option* option = sub->get_option_no_throw(m[1].str()))
          accepted = " (" + option->get_description() + ")";
    return m[1].str() + ": needs a value" + accepted;
  }
  return what + " (see 'lava --help')";
}

// A library error about a parameter, named as the program's user knows it: a scene key
// given as a flag, --device or LAVA_DEVICE, or the key of a scene file as it stands.
std::string parameterMessage(const lava::InvalidArgument& e) {
  const std::string& p = e.parameter();
  if (p == "device")
    return std::string(lava::app::deviceSource()) + ": " + e.detail() + " (see 'lava info')";
  if (p == "particles") return "--particles: " + e.detail() + " (see 'lava info')";
  for (const lava::SceneKey& key : lava::sceneKeys(lava::KeyTable::Top))
    if (p == key.name) return "--" + p + ": " + e.detail();
  return e.what();
}

}  // namespace

namespace lava::app {

Command::Command(CLI::App& app, const char* name, const char* description)
    : command_(app.add_subcommand(name, description)) {}

bool Command::chosen() const {
  return command_->parsed();
}

int runCommandLine(int argc, char** argv, bool parseOnly) {
  parseOnlyMode() = parseOnly;
  CLI::App app{"Lava: a Vulkan compute-shader particle engine (the lava crater)", "lava"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "print help for every command");
  app.set_version_flag("--version", std::string("lava ") + lava::versionString());
  std::vector<std::unique_ptr<lava::app::Command>> commands;
  commands.push_back(lava::app::makeDemo(app));
  commands.push_back(lava::app::makeSimulate(app));
  commands.push_back(lava::app::makeValidate(app));
  commands.push_back(lava::app::makeRender(app));
  commands.push_back(lava::app::makeBench(app));
  commands.push_back(lava::app::makeInfo(app));
  commands.push_back(lava::app::makeStudy(app));

  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + sub->get_name();
      found = found || sub->get_name() == argv[1];
    }
    if (!found) {
      std::fprintf(stderr, "lava: unknown command '%s' (accepted: %s)\n", argv[1], known.c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "lava: %s\n", usageMessage(app, argc > 1 ? argv[1] : nullptr, e).c_str());
    return 2;
  }

  try {
    for (auto& command : commands)
      if (command->chosen()) return command->run();
  } catch (const ParsedOnly&) {
    return 0;
  } catch (const lava::app::UsageError& e) {
    std::fprintf(stderr, "lava: %s\n", e.what());
    return 2;
  } catch (const lava::InvalidArgument& e) {
    std::fprintf(stderr, "lava: %s\n", parameterMessage(e).c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "lava: out of host memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lava: %s\n", e.what());
    return 1;
  }
  return 2;
}

}  // namespace lava::app
