// Fault injection: each command's fallible Vulkan calls, failed in turn through the fault
// layer, and the program without a Vulkan driver.
#include "cli_test.h"

namespace {
using namespace cli;

// Fault injection: each command's fallible Vulkan calls, found by a first run
// through the fault layer, each made to fail at every call (or, for one called more than 12
// times, at five of them: see callsToFail) and at the first call from each of its call
// sites (the layer tells them apart by the return addresses in the program), with one of
// the results it may return. Every time: exit 1, one line naming the call (or the
// allocation) and the result, no partial output, no hang.
struct FaultCommand {
  const char* name;
  const char* args;  // OUT: the output file or folder
  bool folder;       // OUT is a folder of frames: whatever is there must be whole
};

void PrintTo(const FaultCommand& c, std::ostream* os) {
  *os << c.name;
}

class FaultInjection : public ::testing::TestWithParam<FaultCommand> {};

std::vector<std::string> resultsFor(const std::string& function) {
  static const std::set<std::string> canLoseTheDevice = {
      "vkQueueSubmit", "vkWaitForFences", "vkQueueWaitIdle", "vkDeviceWaitIdle",
      "vkGetQueryPoolResults", "vkCreateDevice", "vkMapMemory"};
  std::vector<std::string> r = {"VK_ERROR_OUT_OF_DEVICE_MEMORY", "VK_ERROR_OUT_OF_HOST_MEMORY"};
  if (canLoseTheDevice.count(function)) r.push_back("VK_ERROR_DEVICE_LOST");
  return r;
}

bool wholePng(const std::string& bytes) {
  return bytes.size() > 20 && bytes.compare(1, 3, "PNG") == 0 &&
         bytes.compare(bytes.size() - 8, 4, "IEND") == 0;
}

// Which of a function's n calls to fail: every one when there are at most 12 (each is its
// own call site: setup, allocations, the read-back), else the first two, the middle one and
// the last two (the same site repeated per frame or per batch of steps).
std::set<unsigned long long> callsToFail(unsigned long long n) {
  std::set<unsigned long long> calls;
  if (n <= 12) {
    for (unsigned long long k = 1; k <= n; ++k) calls.insert(k);
  } else {
    calls = {1, 2, n / 2, n - 1, n};
  }
  return calls;
}

TEST_P(FaultInjection, EveryFailingCallExitsOneWithOneLineAndNoPartialOutput) {
  const FaultCommand& c = GetParam();
  const std::string out = scratch(std::string("fault_") + c.name + (c.folder ? "" : ".out"));
  auto args = [&] {
    std::string a = c.args;
    if (const size_t at = a.find("OUT"); at != std::string::npos) a.replace(at, 3, out);
    return a;
  };
  const std::string layer = std::string("env LAVA_VALIDATION=0 VK_LAYER_PATH=") +
                            LAVA_FAULT_LAYER_DIR + " VK_INSTANCE_LAYERS=VK_LAYER_LAVA_fault ";
  const std::string counts = scratch("fault_counts.txt");
  const Result first = lava(args(), layer + "LAVA_FAULT_COUNTS=" + counts + " ");
  ASSERT_EQ(first.status, 0) << first.err;
  std::map<std::string, unsigned long long> calls;
  std::map<std::string, std::set<unsigned long long>> siteCalls;  // each site's first call
  size_t sites = 0;
  {
    std::ifstream in(counts);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::string word, function, where;
      unsigned long long n = 0;
      words >> word;
      if (word == "site") {
        words >> function >> n >> where;
        ASSERT_NE(where, "unknown") << "the layer found no caller for " << line;
        siteCalls[function].insert(n);
        ++sites;
      } else {
        words >> n;
        calls[word] = n;
      }
    }
  }
  ASSERT_GE(calls.size(), 4u) << "the layer saw the command's calls";
  ASSERT_GE(sites, calls.size()) << "every function has at least one call site";
  for (const auto& [function, n] : calls)
    EXPECT_EQ(siteCalls[function].count(1), 1u) << function << "'s first call has a site";
  const std::string whole = c.folder ? "" : readFile(out);
  size_t runs = 0, rotation = 0, bySiteOnly = 0;
  for (const auto& [function, n] : calls) {
    const std::vector<std::string> results = resultsFor(function);
    std::set<unsigned long long> toFail = callsToFail(n);
    for (unsigned long long call : siteCalls[function]) bySiteOnly += toFail.insert(call).second;
    for (unsigned long long call : toFail) {
      // The device's destructor waits once more after the command's own final wait has
      // succeeded; nothing is left to fail then (and a destructor cannot report).
      if (function == "vkDeviceWaitIdle" && call == n && n > 1) continue;
      const std::string result = results[rotation++ % results.size()];
      run("rm -rf " + out);
      const std::string fault = function + ":" + std::to_string(call) + ":" + result;
      const Result r = lava(args(), layer + "LAVA_FAULT=" + fault + " timeout 120 ");
      ++runs;
      SCOPED_TRACE(std::string(c.name) + " with " + fault);
      EXPECT_EQ(r.status, 1) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_NE(r.err.find(result), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(function.substr(2)), std::string::npos) << r.err;
      if (c.folder) {
        const Result files = run("ls -A " + out + " 2>/dev/null");
        std::istringstream names(files.out);
        std::string name;
        while (names >> name) {
          EXPECT_EQ(name.rfind("frame_", 0), 0u) << "a stray file " << name;
          EXPECT_TRUE(wholePng(readFile(out + "/" + name))) << name;
        }
      } else if (access(out.c_str(), F_OK) == 0) {  // only when the run had written it all
        EXPECT_EQ(readFile(out), whole) << "a partial " << out;
      }
    }
  }
  EXPECT_GE(runs, 4u);
  std::printf("%s: %zu functions, %zu call sites, %zu failing runs (%zu for sites no other run "
              "reached)\n",
              c.name, calls.size(), sites, runs, bySiteOnly);
}

INSTANTIATE_TEST_SUITE_P(
    Commands, FaultInjection,
    ::testing::Values(FaultCommand{"simulate", "simulate --steps 300 --out OUT.npy", false},
                      FaultCommand{"checkpoint", "simulate --steps 300 --checkpoint OUT.npz", false},
                      FaultCommand{"validate", "validate --steps 300 --every 100 --csv OUT.csv",
                                   false},
                      FaultCommand{"render", "render --frames 2 --size 160x90 --out OUT", true},
                      FaultCommand{"bench",
                                   "bench --sizes 65536 --steps 20 --backends gpu --json OUT.json",
                                   false},
                      FaultCommand{"demo", "demo --headless --frames 2 --size 160x90 --out OUT",
                                   true},
                      FaultCommand{"info", "info", false}),
    [](const ::testing::TestParamInfo<FaultCommand>& param) { return std::string(param.param.name); });

TEST(Environment, NoVulkanDriverIsOneClearLine) {
  const Result r = lava(
      "info", "env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("no Vulkan"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Environment, CpuBackendNeedsNoVulkan) {
  const Result r =
      lava("simulate --steps 100 --backend cpu",
           "env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.status, 0) << r.err;
}

}  // namespace
