// `lava validate` and its suites: bit-exact tables, JUnit and CSV reports, baselines and
// recorded hashes.
#include "cli_test.h"

namespace {
using namespace cli;

TEST(Validate, SaysBitExactOnLavapipe) {
  const std::string csv = scratch("table.csv");
  const Result r =
      lava("validate --particles 20000 --rate 7000 --steps 3000 --every 500 --csv " + csv);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("first divergent step: none (bit-exact over 3000 steps)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("validate: PASS"), std::string::npos);
  const std::string table = readFile(csv);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 7) << table;  // header + 6 checkpoints
  EXPECT_NE(table.find("3000,20000,20000,20000,0,0,0"), std::string::npos) << table;  // all alive
}

TEST(Validate, AgainstCpuSimdTheSameTable) {
  // --reference cpu-simd: the faster CPU side gives the scalar reference's table.
  const std::string a = scratch("ref.csv"), b = scratch("simd.csv");
  const std::string args = "validate --scene " + std::string(LAVA_SOURCE_DIR) +
                           "/scenes/volcano.toml --steps 600 --every 200 --csv ";
  ASSERT_EQ(lava(args + a).status, 0);
  const Result r = lava(args + b + " --reference cpu-simd");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find(" vs cpu-simd "), std::string::npos) << r.out;
  EXPECT_EQ(readFile(a), readFile(b));
  EXPECT_NE(lava("validate --suite builtin --cases seed-scene --reference cpu-simd")
                .out.find("vs cpu-simd"),
            std::string::npos);
}

// A suite of two passing cases and a canary, which fails on purpose after step 150.
const std::string kSuite = writeScene("suite.toml", R"(
[[case]]
name = "fountain"
steps = 400
particles = 3000
rate = 2000
[[case.collider]]
type = "sphere"
position = [0, 2, 0]
radius = 0.5

[[case]]
name = "seed"
steps = 300

[[case]]
name = "canary"
steps = 300
every = 100
canary = 150
)");

TEST(Suite, BuiltinPassesWithParsableReports) {
  // The reports of a third of the cases (Drivers.*.BuiltinSuite run them all on each driver).
  const std::string junit = scratch("builtin.xml"), results = scratch("builtin.csv");
  const char* chosen[] = {"seed-scene",          "emitter-sphere",     "force-vortex",
                          "collider-cone",       "bursts-lifetimes",   "serial-crosses-2^32",
                          "ring-wraps-within-a-dispatch"};
  std::string names;
  for (const char* name : chosen) names += (names.empty() ? "" : ",") + std::string(name);
  const Result r = lava("validate --suite builtin --cases " + names + " --junit " + junit +
                        " --results " + results);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  const std::string csv = readFile(results);
  EXPECT_EQ(csv.substr(0, 55), "case,status,steps,first_divergent_step,max_ulp,seconds\n");
  const int cases = count(csv, "\n") - 1;
  EXPECT_EQ(cases, 7);
  EXPECT_EQ(count(csv, ",Pass,"), cases) << csv;
  for (const char* name : chosen)
    EXPECT_NE(csv.find(std::string(name) + ",Pass"), std::string::npos) << name;
  // The suite's 21 cases, which an unknown name lists.
  const Result listed = lava("validate --suite builtin --cases none");
  EXPECT_EQ(count(listed.err, ", "), 20) << listed.err;
  for (const char* name : {"integrator-velocity-verlet", "beyond-one-binding", "all", "flow"})
    EXPECT_NE(listed.err.find(std::string(" ") + name), std::string::npos) << name;
  // The XML parses, with one testcase per case and the device among its properties.
  const Result parsed =
      run("/usr/bin/python3 -c \"import xml.etree.ElementTree as E; "
          "t = E.parse('" +
          junit +
          "'); "
          "print(len(t.findall('.//testcase')), len(t.findall('.//failure')), "
          "t.find('.//property').get('value'))\"");
  EXPECT_EQ(parsed.status, 0) << parsed.err;
  EXPECT_EQ(parsed.out.substr(0, parsed.out.find(' ')), std::to_string(cases)) << parsed.out;
  EXPECT_NE(parsed.out.find(" 0 llvmpipe"), std::string::npos) << parsed.out;
}

TEST(Suite, AFailureIsNamedAndBaselinesDecideTheExitStatus) {
  const std::string junit = scratch("canary.xml"), results = scratch("canary.csv");
  Result r = lava("validate --suite " + kSuite + " --junit " + junit + " --results " + results);
  EXPECT_EQ(r.status, 1) << r.out;
  const std::string xml = readFile(junit);
  EXPECT_EQ(count(xml, "<testcase "), 3);
  EXPECT_EQ(count(xml, "<failure "), 1);
  for (const char* detail :
       {"first divergent step 150", "particle 0 (emitter 0)", "field vy", "gpu 0x", "cpu 0x"})
    EXPECT_NE(xml.find(detail), std::string::npos) << detail << "\n" << xml;
  EXPECT_NE(readFile(results).find("canary,Fail,300,150,1,"), std::string::npos);
  const std::string expected = writeScene("baseline.txt", "# known\ncanary,Fail\n");
  r = lava("validate --suite " + kSuite + " --baseline " + expected + " --results " + results);
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(readFile(results).find("canary,ExpectedFail"), std::string::npos);
  const std::string wrong = writeScene("baseline2.txt", "canary,Fail\nseed,Fail\n");
  r = lava("validate --suite " + kSuite + " --baseline " + wrong + " --results " + results);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(readFile(results).find("seed,UnexpectedPass"), std::string::npos);
}

TEST(Suite, CasesRunsOnlyTheNamedCasesInTheSuitesOrder) {
  const std::string results = scratch("chosen.csv");
  const Result r = lava("validate --suite " + kSuite + " --cases canary,seed --results " + results);
  EXPECT_EQ(r.status, 1) << r.out;  // the canary still fails
  const std::string csv = readFile(results);
  EXPECT_EQ(count(csv, "\n"), 3) << csv;
  EXPECT_LT(csv.find("\nseed,Pass"), csv.find("\ncanary,Fail")) << csv;
  EXPECT_EQ(csv.find("fountain"), std::string::npos) << csv;
}

TEST(Suite, RecordedHashesAgreeAndCatchAChangedSeed) {
  const std::string recording = scratch("hashes.csv");
  ASSERT_EQ(lava("validate --suite " + kSuite + " --record " + recording).status, 1);
  EXPECT_EQ(readFile(recording).substr(0, 15), "case,step,hash\n");
  Result r = lava("validate --suite " + kSuite + " --against " + recording);
  EXPECT_EQ(r.status, 0) << r.out;  // GPU against GPU: the canary only nudges the CPU
  r = lava("validate --suite " + kSuite + " --against " + recording + " --seed 5");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("the recording has"), std::string::npos) << r.out;
}

}  // namespace
