// The command line: the input split at NUL bytes into arguments after `lava`, parsed up to
// the point where a command would start work (runCommandLine's parseOnly): any exit status,
// never a crash, a hang or a leak. Scene and checkpoint files it names are read.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cli.h"
#include "tools/fuzzing.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  lava::compareCheckpointSums(false);  // docs/fuzzing.md
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> words{"lava"};
  std::string word;
  for (size_t i = 0; i < size && words.size() < 32; ++i) {
    if (data[i] == 0) {
      words.push_back(word);
      word.clear();
    } else {
      word += char(data[i]);
    }
  }
  if (!word.empty() && words.size() < 32) words.push_back(word);
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  lava::app::runCommandLine(int(words.size()), argv.data(), true);
  std::fflush(stdout);
  return 0;
}
