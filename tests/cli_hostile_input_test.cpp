// Bad input to the `lava` program: every bad flag, scene key and file exits 2 with one line
// naming it and what is accepted, and leaves no output behind.
#include "cli_test.h"

namespace {
using namespace cli;

struct BadInput {
  const char* args;
  const char* mentions;  // the flag or key the one-line message must name
};

void PrintTo(const BadInput& c, std::ostream* os) {
  *os << "lava " << c.args;
}

// Test names: the arguments with every non-alphanumeric run turned into '_'.
std::string caseName(const ::testing::TestParamInfo<BadInput>& info) {
  std::string name = std::to_string(info.index) + "_";
  for (const char* p = info.param.args; *p; ++p)
    name += std::isalnum(static_cast<unsigned char>(*p)) ? *p : '_';
  return name;
}

class HostileInput : public ::testing::TestWithParam<BadInput> {};

// The paths a command line names after an output flag, and whether each exists now.
std::map<std::string, bool> outputsOf(const std::string& args) {
  std::map<std::string, bool> paths;
  std::istringstream words(args);
  std::string word, previous;
  while (words >> word) {
    for (const char* flag : {"--out", "--csv", "--json", "--video", "--junit", "--results",
                             "--record", "--checkpoint", "--series"})
      if (previous == flag) paths[word] = access(word.c_str(), F_OK) == 0;
    previous = word;
  }
  return paths;
}

TEST_P(HostileInput, ExitsTwoWithOneLineNamingTheProblem) {
  const BadInput& c = GetParam();
  const auto before = outputsOf(c.args);
  const Result r = lava(c.args);
  for (const auto& [path, existed] : before)  // nothing created: no file, no empty folder
    if (!existed) {
      EXPECT_NE(access(path.c_str(), F_OK), 0) << c.args << " left " << path;
    }
  EXPECT_EQ(r.status, 2) << c.args << "\nstderr: " << r.err;
  EXPECT_NE(r.err.find(c.mentions), std::string::npos) << c.args << "\nstderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.out, "");
}

const std::string kGarbageScene =
    writeScene("garbage.toml", std::string("\x00\xff\x13[[[=\x80", 8));

const std::string kUnknownKey =
    writeScene("unknown.toml", "particles = 100\nlava_temperature = 3\n");

const std::string kWrongType = writeScene("type.toml", "restitution = \"high\"\n");

const std::string kWrongArity = writeScene("arity.toml", "emitter = [1.0, 2.0]\n");

const std::string kBadRange = writeScene("range.toml", "friction = 2.5\n");

const std::string kNanScene = writeScene("nan.toml", "restitution = nan\n");

const std::string kInfScene = writeScene("inf.toml", "gravity = -inf\n");

const std::string kNegativeCount = writeScene("negative.toml", "particles = -5\n");

const std::string kBoolScene = writeScene("bool.toml", "mass = true\n");

const std::string kTableScene = writeScene("table.toml", "[emitter]\nx = 1\n");

const std::string kUnknownType = writeScene("type2.toml", "[[collider]]\ntype = \"torus\"\n");

const std::string kZeroNormal =
    writeScene("normal.toml", "[[collider]]\ntype = \"plane\"\nnormal = [0, 0, 0]\n");

const std::string kNegativeSize =
    writeScene("size.toml", "[[emitter]]\n[[emitter]]\nshape = \"box\"\nsize = [1, -1, 1]\n");

const std::string kShortVector = writeScene("arity2.toml", "[[force]]\naxis = [0, 1]\n");

const std::string kSeventeen = writeScene("many.toml", [] {
  std::string s;
  for (int i = 0; i < 17; ++i) s += "[[emitter]]\nparticles = 10\n";
  return s;
}());

const BadInput kBadInputs[] = {
    {"simulate --steps 10 --restitution abc", "--restitution"},
    {"simulate --steps 10 --restitution 1.5", "--restitution"},
    {"simulate --steps 10 --restitution nan", "--restitution"},
    {"simulate --steps 10 --friction -0.1", "--friction"},
    {"simulate --steps 10 --mass 0", "--mass"},
    {"simulate --steps 10 --mass inf", "--mass"},
    {"simulate --steps 10 --dt 0", "--dt"},
    {"simulate --steps 10 --dt -1", "--dt"},
    {"simulate --steps 10 --particles 0", "--particles"},
    {"simulate --steps 10 --particles 12abc", "--particles"},
    {"simulate --steps 10 --particles -5", "--particles"},
    {"simulate --steps 10 --particles 1.5", "--particles"},
    {"simulate --steps 10 --particles 99999999999", "--particles"},
    {"simulate --steps 10 --emitter 1,2", "--emitter"},
    {"simulate --steps 10 --emitter 1,2,3,4", "--emitter"},
    {"simulate --steps 10 --velocity 1,,2", "--velocity"},
    {"simulate --steps 10 --spread -1,0,0", "--spread"},
    {"simulate --steps 10 --gravity 1e9", "--gravity"},
    {"simulate --steps 10 --seed 4294967296", "--seed"},
    {"simulate --steps 10 --rate -3", "--rate"},
    {"simulate --steps 10 --series hostile-series --every 0", "--every"},
    {"simulate --steps 10 --series hostile-series --every x", "--every"},
    {"simulate --steps 10 --series hostile-series --every 1e10", "--every"},
    {"simulate --steps 10 --series hostile-series", "--series"},
    {"simulate --steps 10 --every 5", "--every"},
    {"simulate --steps 10 --series . --every 5", "--series"},
    {"simulate --steps 10 --series / --every 5", "--series"},
    {"simulate --steps 10 --series /nonexistent/run --every 5", "--series"},
    {"simulate --steps 10 --series /dev/null --every 5", "--series"},
    {"render --frames 1 --out hostile-frames --series hostile-series", "--series"},
    {"render --frames 1 --out hostile-frames --every 3", "--every"},
    {"render --frames 1 --out hostile-frames --series . --every 3", "--series"},
    {"simulate --steps 10 --line-scale 11", "--line-scale"},
    {"simulate --steps 10 --drag -1", "--drag"},
    {"simulate --steps 10 --wind 1,2", "--wind"},
    {"simulate --steps -1", "--steps"},
    {"simulate --steps abc", "--steps"},
    {"simulate", "--steps"},
    {"simulate --steps 10 --lava-temperature 3", "--lava-temperature"},
    {"simulate --steps 10 --backend tpu", "--backend"},
    {"render --frames 1 --out hostile-frames --backend gpu,cpu", "--backend"},
    {"render --frames 1 --out hostile-frames --threads 1025", "--threads"},
    {"simulate --steps 10 --threads -2", "--threads"},
    {"simulate --steps 10 --out /nonexistent/dir/state.npy", "--out"},
    {"simulate --steps 10 --out state.txt", "--out"},
    {"simulate --steps 10 --out .npy", "--out"},
    {"simulate --steps 10 --device 99", "--device"},
    {"simulate --steps 10 --dt 1e-50", "--dt"},
    {"simulate --steps 10 --rate 1e400", "--rate"},
    {"simulate --steps 10 --velocity 1,2,3,", "--velocity"},
    {"validate --steps 10 --tolerance-ulp -1", "--tolerance-ulp"},
    {"validate --steps 10 --reference gpu", "--reference"},
    {"bench --backends cpu,simd", "--backends"},
    {"bench --simd-target MMX", "--simd-target"},
    {"validate --steps 10 --every 0", "--every"},
    {"validate --steps 0", "--steps"},
    {"validate --steps 10 --csv table.txt", "--csv"},
    {"info --device 42", "--device"},
    {"render --frames 2 --size 0x0 --out frames", "--size"},
    {"render --frames 2 --size 640by480 --out frames", "--size"},
    {"render --frames 0 --out frames", "--frames"},
    {"render --frames 2 --fps 0 --out frames", "--fps"},
    {"render --frames 2 --out /proc/lava-frames", "--out"},
    {"render --frames 2", "--out"},
    {"render --frames 2 --renderer raytrace --out frames", "--renderer"},
    {"demo --renderer raytrace", "--renderer"},
    {"render --frames 2 --look neon --out frames", "--look"},
    {"render --frames 2 --exposure 0 --out frames", "--exposure"},
    {"render --frames 2 --exposure 17 --out frames", "--exposure"},
    {"render --frames 2 --bloom -1 --out frames", "--bloom"},
    {"render --frames 2 --bloom nan --out frames", "--bloom"},
    {"render --frames 2 --bloom-threshold 99 --out frames", "--bloom-threshold"},
    {"demo --look 1", "--look"},
    {"demo --exposure x", "--exposure"},
    {"demo --present mirror", "--present"},
    {"demo --vsync --present shm", "--vsync"},
    {"bench --sizes 0", "--sizes"},
    {"bench --sizes 1000,abc", "--sizes"},
    {"bench --sizes 1000,", "--sizes"},
    {"bench --sizes 99999999999", "--sizes"},
    {"bench --steps 0", "--steps"},
    {"bench --steps-per-dispatch 300", "--steps-per-dispatch"},
    {"bench --backends tpu", "--backends"},
    {"bench --json results.txt", "--json"},
    {"frobnicate", "frobnicate"},
    {"simulate --steps 10 extra", "extra"},
    {"simulate --steps 10 --steps 20", "--steps: given 2 times; give it once"},
    {"simulate --steps", "--steps: needs a value (steps to run"},
    {"demo --frames", "--frames: needs a value"},
    {"", "subcommand"},
};

INSTANTIATE_TEST_SUITE_P(Flags, HostileInput, ::testing::ValuesIn(kBadInputs), caseName);

const BadInput kBadScenes[] = {
    {"simulate --steps 1 --scene /nonexistent.toml", "--scene"},
    {"simulate --steps 1 --scene ", "--scene"},
};

INSTANTIATE_TEST_SUITE_P(MissingScene, HostileInput, ::testing::ValuesIn(kBadScenes), caseName);

TEST(SceneFile, HostileScenesExitTwoNamingTheKey) {
  const std::pair<std::string, std::string> cases[] = {
      {kGarbageScene, "--scene"},
      {kUnknownKey, "lava_temperature"},
      {kWrongType, "restitution"},
      {kWrongArity, "emitter"},
      {kBadRange, "friction"},
      {kNanScene, "restitution"},
      {kInfScene, "gravity"},
      {kNegativeCount, "particles"},
      {kBoolScene, "mass"},
      {kTableScene, "emitter"},
      {kUnknownType, "collider[0].type"},
      {kZeroNormal, "collider[0].normal"},
      {kNegativeSize, "emitter[1].size"},
      {kShortVector, "force[0].axis"},
      {kSeventeen, "at most 16 [[emitter]]"},
  };
  for (const auto& [path, mentions] : cases) {
    const Result r = lava("simulate --steps 1 --scene " + path);
    EXPECT_EQ(r.status, 2) << path << ": " << r.err;
    EXPECT_NE(r.err.find(mentions), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST(Simulate, BadInputLeavesNoFileBehind) {
  const std::string out = scratch("never.npy");
  std::remove(out.c_str());
  EXPECT_EQ(lava("simulate --steps 10 --mass -1 --out " + out).status, 2);
  EXPECT_FALSE(std::ifstream(out).good());
  EXPECT_FALSE(std::ifstream(out + ".partial").good());
}

TEST(Checkpoint, DamagedFilesExitTwoAndOverwriteNothing) {
  const std::string ck = scratch("good.npz"), out = scratch("kept.npy");
  ASSERT_EQ(lava("simulate --steps 200 --checkpoint " + ck + " --out " + out).status, 0);
  const std::string good = readFile(ck), kept = readFile(out);
  const std::string truncated = writeScene("truncated.npz", good.substr(0, good.size() / 2));
  std::string flipped = good;
  flipped[good.size() / 3] = char(flipped[good.size() / 3] ^ 1);
  const std::string corrupt = writeScene("corrupt.npz", flipped);
  const std::string text = writeScene("text.npz", "particles = 5\n");
  struct Case {
    std::string file, says;
  };
  for (const Case& c : {Case{truncated, "truncated"}, Case{corrupt, "mismatch"},
                        Case{text, "not a checkpoint"}, Case{scratch("missing.npz"), "cannot read"}}) {
    const Result r = lava("simulate --resume " + c.file + " --steps 10 --out " + out);
    EXPECT_EQ(r.status, 2) << c.file;
    EXPECT_NE(r.err.find("--resume: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  const Result p = lava("simulate --resume " + ck + " --steps 10 --particles 99 --out " + out);
  EXPECT_EQ(p.status, 2);
  EXPECT_NE(p.err.find("--particles: 99 disagrees with the checkpoint's 5000"), std::string::npos)
      << p.err;
  EXPECT_EQ(lava("simulate --resume " + ck + " --scene x.toml --steps 1").status, 2);
  EXPECT_EQ(readFile(out), kept);  // nothing overwritten
  EXPECT_EQ(readFile(ck), good);
}

TEST(Suite, BadSuitesAreUsageErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {"[[case]]\nsteps = 10\n", "case[0].name"},
      {"[[case]]\nname = \"a\"\n", "case[0].steps"},
      {"[[case]]\nname = \"a\"\nsteps = 10\n[[case]]\nname = \"a\"\nsteps = 5\n", "twice"},
      {"[[case]]\nname = \"a\"\nsteps = 10\nrestitution = 3\n", "case[0]: restitution"},
      {"[[case]]\nname = \"a\"\nsteps = 10\nscene = \"/nonexistent.toml\"\n", "nonexistent"},
      {"title = \"x\"\n", "title"},
  };
  for (const auto& [suite, mentions] : cases) {
    const Result r = lava("validate --suite " + writeScene("bad-suite.toml", suite));
    EXPECT_EQ(r.status, 2) << suite << r.err;
    EXPECT_NE(r.err.find(mentions), std::string::npos) << suite << r.err;
    EXPECT_EQ(count(r.err, "\n"), 1) << r.err;
  }
  EXPECT_EQ(lava("validate --steps 10 --junit " + scratch("x.xml")).status, 2);
  EXPECT_EQ(lava("validate --suite builtin --steps 10").status, 2);
  EXPECT_EQ(lava("validate --suite /nonexistent.toml").status, 2);
  for (const auto& [flags, mentions] : std::vector<std::pair<std::string, std::string>>{
           {"--suite builtin --cases seed-scene,nothing", "no case 'nothing'"},
           {"--suite builtin --cases seed-scene,,all", "--cases"},
           {"--suite builtin --cases all,all", "--cases"},
           {"--steps 10 --cases all", "needs --suite"}}) {
    const Result r = lava("validate " + flags);
    EXPECT_EQ(r.status, 2) << flags << r.err;
    EXPECT_NE(r.err.find(mentions), std::string::npos) << flags << r.err;
    EXPECT_EQ(count(r.err, "\n"), 1) << r.err;
  }
}

TEST(Environment, BadLavaDeviceIsAUsageError) {
  const Result r = lava("info", "env LAVA_DEVICE=seven ");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("LAVA_DEVICE"), std::string::npos) << r.err;
}

TEST(Render, AUsageErrorLeavesNoFolderBehind) {
  const std::string folder = scratch("never");
  run("rm -rf " + folder);
  EXPECT_EQ(lava("render --frames 2 --size 20000x20000 --out " + folder).status, 2);
  EXPECT_EQ(lava("render --frames 2 --fps 0 --out " + folder).status, 2);
  EXPECT_NE(access(folder.c_str(), F_OK), 0);
}

TEST(Help, UnknownFlagsAndKeysSuggestTheNearest) {
  Result r = lava("simulate --steps 1 --emitter_radius 0.2");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--emitter_radius: unknown flag; did you mean --emitter-radius?"),
            std::string::npos)
      << r.err;
  const std::string scene = writeScene("typo.toml", "[[emitter]]\nradus = 0.2\n");
  r = lava("simulate --steps 1 --scene " + scene);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean radius?"), std::string::npos) << r.err;
  r = lava("bench --particles 1000");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--particles: bench sets the counts with --sizes"), std::string::npos)
      << r.err;
}

TEST(HostileInput, LimitsOfThisDeviceAreUsageErrors) {
  // Past what this device holds, whatever it is: its largest particle count plus one, and an
  // image one pixel past its limit (lavapipe: 67,108,864 and 16,384).
  const Result info = lava("info");
  const unsigned long long particles = infoNumber(info.out, "largest particle count");
  const unsigned long long side = infoNumber(info.out, "maxImageDimension2D");
  ASSERT_GT(particles, 0u);
  ASSERT_GT(side, 0u);
  Result r = lava("simulate --steps 10 --particles " + std::to_string(particles + 1));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("--particles"), std::string::npos) << r.err;
  const std::string folder = scratch("toolarge");
  if (side < 65536) {
    r = lava("render --frames 1 --size " + std::to_string(side + 1) + "x16 --out " + folder);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--size"), std::string::npos) << r.err;
    EXPECT_NE(access(folder.c_str(), F_OK), 0);
  }
}

}  // namespace

namespace lava {
namespace {

TEST(ResourceLimits, AStateBeyondHostMemoryIsRefusedUpFront) {
  // 2^31 particles need 128 GiB of host memory for a state and its copy: every backend
  // refuses them before allocating, in one line naming the flag and the limit (the GPU's
  // own limit first where it is lower), never "out of host memory" from a failed allocation.
  for (const char* backend : {"cpu", "cpu-simd", "gpu"}) {
    SCOPED_TRACE(backend);
    const cli::Result r = cli::lava(std::string("simulate --steps 1 --particles 2147483648 "
                                                "--backend ") + backend);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(cli::count(r.err, "\n"), 1) << r.err;
    EXPECT_EQ(r.err.rfind("lava: --particles: 2147483648 particles need ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find("out of host memory"), std::string::npos) << r.err;
    if (std::string(backend) != "gpu") {
      EXPECT_NE(r.err.find("MiB of host memory for their state; this machine has "),
                std::string::npos)
          << r.err;
    }
  }
}

}  // namespace
}  // namespace lava
