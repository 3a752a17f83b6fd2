// The `lava` program as users and outside checks call it: exit codes, one-line messages
// naming the flag, scene files, and outputs that appear whole or not at all.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace {

struct Result {
  int status;
  std::string out;
  std::string err;
};

std::string readFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream s;
  s << file.rdbuf();
  return s.str();
}

// This process's scratch folder, removed when the tests end (a forked child sees the same).
const std::string& scratchFolder() {
  static const std::string folder = [] {
    const std::string path = ::testing::TempDir() + "lava_cli_" + std::to_string(getpid()) + "/";
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}

std::string scratch(const std::string& name) { return scratchFolder() + name; }

class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(scratchFolder(), ignored);
  }
};
const auto* const removeScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

// Runs a shell command line, capturing its exit status and output.
Result run(const std::string& command) {
  const std::string out = scratch("stdout"), err = scratch("stderr");
  const std::string line = command + " >" + out + " 2>" + err + " </dev/null";
  const int raw = std::system(line.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), readFile(out), readFile(err)};
}

// Runs build/lava with `args`; `prefix` goes before it (e.g. an `env` call).
Result lava(const std::string& args, const std::string& prefix = "") {
  return run(prefix + std::string(LAVA_EXE) + " " + args);
}

std::string writeScene(const std::string& name, const std::string& contents) {
  const std::string path = scratch(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

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
                             "--record", "--checkpoint"})
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
    {"simulate --steps 10 --line-scale 11", "--line-scale"},
    {"simulate --steps 10 --drag -1", "--drag"},
    {"simulate --steps 10 --wind 1,2", "--wind"},
    {"simulate --steps -1", "--steps"},
    {"simulate --steps abc", "--steps"},
    {"simulate", "--steps"},
    {"simulate --steps 10 --lava-temperature 3", "--lava-temperature"},
    {"simulate --steps 10 --backend tpu", "--backend"},
    {"simulate --steps 10 --threads -2", "--threads"},
    {"simulate --steps 10 --out /nonexistent/dir/state.npy", "--out"},
    {"simulate --steps 10 --out state.txt", "--out"},
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

size_t npyRows(const std::string& path) {
  const std::string data = readFile(path);
  const size_t at = data.find("'shape': (");
  return at == std::string::npos ? 0 : std::stoul(data.substr(at + 10));
}

TEST(SceneFile, SetsValuesAndTheCommandLineWins) {
  const std::string scene = writeScene("ok.toml",
                                       "particles = 100\nrestitution = 0.9\n"
                                       "emitter = [0.0, 1.0, 0.0]\nsteps = 20\n");
  const std::string out = scratch("scene.npy");
  Result r = lava("simulate --scene " + scene + " --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(npyRows(out), 100u);
  r = lava("simulate --scene " + scene + " --particles 200 --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(npyRows(out), 200u);
}

TEST(SceneFile, OneSceneServesEveryCommand) {
  // `steps` belongs to simulate/validate/bench, `frames` to render/demo: each command uses
  // its own keys and passes over the others' (a typo is still an unknown key).
  const std::string scene = writeScene("shared.toml",
                                       "particles = 300\nsteps = 20\nframes = 2\n"
                                       "size = \"64x48\"\n");
  const std::string out = scratch("shared.npy"), frames = scratch("shared-frames");
  Result r = lava("simulate --scene " + scene + " --out " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(npyRows(out), 300u);
  r = lava("render --scene " + scene + " --out " + frames);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("wrote 2 frames (64x48)"), std::string::npos) << r.out;
}

TEST(SceneFile, FormatTwoRowsAreEmitterZeroThenOne) {
  const std::string scene =
      writeScene("two.toml",
                 "[[emitter]]\nparticles = 30\nrate = 0\n[[emitter]]\nparticles = 20\n"
                 "rate = 0\nburst = 20\nshape = \"point\"\nposition = [0, 5, 0]\n");
  const std::string out = scratch("two.csv");
  const Result r = lava("simulate --steps 1 --scene " + scene + " --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream rows(readFile(out));
  std::string line;
  std::getline(rows, line);  // header
  int row = 0, unborn = 0, born = 0;
  while (std::getline(rows, line)) {
    const bool alive = line.substr(line.rfind(',') + 1) != "-1";
    (row < 30 ? unborn : born) += row < 30 ? !alive : alive;
    ++row;
  }
  EXPECT_EQ(row, 50);
  EXPECT_EQ(unborn, 30);  // emitter 0: no births
  EXPECT_EQ(born, 20);    // emitter 1: its burst
}

TEST(Simulate, GpuAndCpuBackendsWriteIdenticalFiles) {
  const std::string gpu = scratch("gpu.npy"), cpu = scratch("cpu.csv"), cpuNpy = scratch("cpu.npy");
  ASSERT_EQ(lava("simulate --steps 1500 --backend gpu --out " + gpu).status, 0);
  ASSERT_EQ(lava("simulate --steps 1500 --backend cpu --out " + cpuNpy).status, 0);
  const Result r = lava("simulate --steps 1500 --backend cpu --out " + cpu);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readFile(gpu), readFile(cpuNpy));
  EXPECT_EQ(readFile(gpu).size(), 128u + 5000u * 7u * 4u);
  const std::string simd = scratch("simd.npy");
  const Result s = lava("simulate --steps 1500 --backend cpu-simd --threads 2 --out " + simd);
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(readFile(simd), readFile(cpuNpy));
  EXPECT_NE(s.out.find("cpu-simd "), std::string::npos) << s.out;
  EXPECT_EQ(readFile(cpu).substr(0, 22), "px,py,pz,vx,vy,vz,age\n");
  EXPECT_NE(r.out.find("1500 steps"), std::string::npos) << r.out;
}

TEST(Simulate, BadInputLeavesNoFileBehind) {
  const std::string out = scratch("never.npy");
  std::remove(out.c_str());
  EXPECT_EQ(lava("simulate --steps 10 --mass -1 --out " + out).status, 2);
  EXPECT_FALSE(std::ifstream(out).good());
  EXPECT_FALSE(std::ifstream(out + ".partial").good());
}

TEST(Simulate, SixteenMillionParticlesPastTheBindingRange) {
  const Result r = lava("simulate --particles 16777216 --steps 5");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("16777216 particles"), std::string::npos) << r.out;
}

TEST(Checkpoint, HalvesResumedGiveTheStraightRunsBytes) {
  // N steps straight, or N/2 to a checkpoint and N/2 resumed from it: identical files, on
  // each backend and crossed over; validate starts from it too.
  const std::string scene = "--scene " + std::string(LAVA_SOURCE_DIR) + "/scenes/volcano.toml";
  const std::string straight = scratch("straight.npy"), ck = scratch("half.npz");
  ASSERT_EQ(lava("simulate " + scene + " --steps 1600 --out " + straight).status, 0);
  for (const char* first : {"gpu", "cpu"})
    for (const char* second : {"gpu", "cpu"}) {
      SCOPED_TRACE(std::string(first) + " then " + second);
      const std::string resumed = scratch("resumed.npy");
      const Result a = lava("simulate " + scene + " --steps 800 --backend " + first +
                            " --checkpoint " + ck);
      ASSERT_EQ(a.status, 0) << a.err;
      EXPECT_NE(a.out.find("checkpoint at step 800"), std::string::npos) << a.out;
      const Result b = lava("simulate --resume " + ck + " --steps 800 --backend " + second +
                            " --out " + resumed);
      ASSERT_EQ(b.status, 0) << b.err;
      EXPECT_EQ(readFile(resumed), readFile(straight));
    }
  const Result v = lava("validate --resume " + ck + " --steps 300 --every 100");
  EXPECT_EQ(v.status, 0) << v.err;
  EXPECT_NE(v.out.find("from step 800"), std::string::npos) << v.out;
  // Every K steps: the file holds the last multiple.
  ASSERT_EQ(lava("simulate --steps 1000 --backend cpu --checkpoint " + ck +
                 " --checkpoint-every 300").status,
            0);
  EXPECT_NE(readFile(ck).size(), 0u);
}

TEST(Checkpoint, SigintWritesItAndTheResumedRunMatchesTheUninterruptedOne) {
  // A long run on the CPU, interrupted mid-way: exit 130 saying after how many steps, the
  // checkpoint written at a step boundary; resumed for 500 more steps it matches a run that
  // took those steps in one go.
  const std::string ck = scratch("interrupted.npz"), log = scratch("interrupted.log");
  std::remove(ck.c_str());
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    freopen(log.c_str(), "w", stdout);
    execl(LAVA_EXE, LAVA_EXE, "simulate", "--particles", "20000", "--rate", "5000", "--backend",
          "cpu", "--threads", "1", "--steps", "1000000", "--checkpoint", ck.c_str(),
          "--checkpoint-every", "1000", static_cast<char*>(nullptr));
    _exit(127);
  }
  // The first periodic checkpoint says the run is under way (its handlers installed).
  for (int i = 0; i < 600 && access(ck.c_str(), F_OK) != 0; ++i) usleep(50 * 1000);
  usleep(300 * 1000);
  kill(child, SIGINT);
  int raw = 0;
  waitpid(child, &raw, 0);
  ASSERT_TRUE(WIFEXITED(raw)) << "killed by signal " << WTERMSIG(raw);
  EXPECT_EQ(WEXITSTATUS(raw), 130);
  const std::string out = readFile(log);
  const size_t after = out.find("interrupted by SIGINT after ");
  ASSERT_NE(after, std::string::npos) << out;
  const unsigned long long done = std::stoull(out.substr(after + 28));
  ASSERT_GT(done, 0u);
  ASSERT_LT(done, 1000000u);
  const std::string resumed = scratch("resumed.npy"), straight = scratch("straight.npy");
  ASSERT_EQ(lava("simulate --resume " + ck + " --steps 500 --backend cpu --out " + resumed).status,
            0);
  ASSERT_EQ(lava("simulate --particles 20000 --rate 5000 --backend cpu --steps " +
                 std::to_string(done + 500) + " --out " + straight)
                .status,
            0);
  EXPECT_EQ(readFile(resumed), readFile(straight));
}

TEST(Simulate, CtrlCSaysSoAndExits130LeavingNoFile) {
  // Without --checkpoint: one line, exit 130, and the --out file not half written.
  const std::string out = scratch("interrupted.npy"), err = scratch("ctrlc.err");
  std::remove(out.c_str());
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    freopen(err.c_str(), "w", stderr);
    execl(LAVA_EXE, LAVA_EXE, "simulate", "--particles", "20000", "--backend", "cpu",
          "--threads", "1", "--steps", "1000000", "--out", out.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  usleep(800 * 1000);
  kill(child, SIGINT);
  int raw = 0;
  waitpid(child, &raw, 0);
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 130);
  EXPECT_NE(readFile(err).find("lava: interrupted"), std::string::npos);
  EXPECT_NE(access(out.c_str(), F_OK), 0);
}

TEST(Simulate, TwoRunsWritingOneFileLeaveOneRunsWholeOutput) {
  // Concurrent writers of the same --out: each writes a temporary of its own and renames it
  // into place, so both succeed and the file is exactly one run's output.
  const std::string out = scratch("shared.npy"), a = scratch("a.npy"), b = scratch("b.npy");
  ASSERT_EQ(lava("simulate --steps 300 --seed 1 --out " + a).status, 0);
  ASSERT_EQ(lava("simulate --steps 300 --seed 2 --out " + b).status, 0);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const Result r = run("(" + std::string(LAVA_EXE) + " simulate --steps 300 --seed 1 --out " +
                         out + " & " + LAVA_EXE + " simulate --steps 300 --seed 2 --out " + out +
                         " & wait)");
    EXPECT_EQ(r.err, "");
    const std::string got = readFile(out);
    EXPECT_TRUE(got == readFile(a) || got == readFile(b)) << "attempt " << attempt;
  }
  // Their temporaries are <out>.XXXXXX beside it; none may be left.
  EXPECT_EQ(run("(ls -A " + scratchFolder() + " | grep -c -F '" +
                out.substr(out.rfind('/') + 1) + ".'; true)").out,
            "0\n");
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

// Fault injection (issue 11): each command's fallible Vulkan calls, found by a first run
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
  EXPECT_NE(lava("validate --suite builtin --reference cpu-simd").out.find("vs cpu-simd"),
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

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Suite, BuiltinPassesWithParsableReports) {
  const std::string junit = scratch("builtin.xml"), results = scratch("builtin.csv");
  const Result r = lava("validate --suite builtin --junit " + junit + " --results " + results);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  const std::string csv = readFile(results);
  EXPECT_EQ(csv.substr(0, 55), "case,status,steps,first_divergent_step,max_ulp,seconds\n");
  const int cases = count(csv, "\n") - 1;
  EXPECT_GE(cases, 20);
  EXPECT_EQ(count(csv, ",Pass,"), cases) << csv;
  for (const char* module :
       {"shape-sphere", "force-vortex", "collider-cone", "integrator-velocity-verlet", "bursts",
        "lifetimes", "beyond-one-binding", "serial-crosses-2^32", "everything"})
    EXPECT_NE(csv.find(std::string(module) + ",Pass"), std::string::npos) << module;
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
}

TEST(Render, WritesPngFrames) {
  const std::string folder = scratch("frames");
  const Result r =
      lava("render --frames 3 --fps 10 --size 160x90 --renderer splat --out " + folder);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"/frame_00000.png", "/frame_00001.png", "/frame_00002.png"})
    EXPECT_EQ(readFile(folder + name).substr(0, 8), "\x89PNG\r\n\x1a\n") << name;
  EXPECT_NE(r.out.find("wrote 3 frames (160x90)"), std::string::npos) << r.out;
}

TEST(Demo, WithoutADisplayRendersHeadlessAndSaysWhere) {
  const std::string folder = scratch("demo-frames");
  const Result r =
      lava("demo --frames 2 --size 160x90 --out " + folder, "env -u DISPLAY -u WAYLAND_DISPLAY ");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("no display"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(folder), std::string::npos) << r.out;
  EXPECT_EQ(readFile(folder + "/frame_00001.png").substr(0, 4), "\x89PNG");
}

TEST(Progress, SimulateValidateAndBenchShowItWithTheTimeLeftOnATerminal) {
  // Under a pseudo-terminal (script(1), util-linux) each long command draws a progress line
  // with the time left; piped, as in every other test, none of it appears.
  const auto onTerminal = [](const std::string& args) {
    return run("script -qfec '" + std::string(LAVA_EXE) + " " + args + "' /dev/null");
  };
  const Result s = onTerminal(
      "simulate --backend cpu --threads 1 --particles 100000 --burst 100000 --steps 3000");
  EXPECT_EQ(s.status, 0) << s.out;
  EXPECT_NE(s.out.find("\r\033[Ksimulate "), std::string::npos) << s.out;
  EXPECT_NE(s.out.find(" s left)"), std::string::npos) << s.out;
  const Result v =
      onTerminal("validate --particles 200000 --burst 200000 --steps 2000 --every 200");
  EXPECT_EQ(v.status, 0) << v.out;
  EXPECT_NE(v.out.find("\r\033[Kvalidate 200/2000 (10%"), std::string::npos) << v.out;
  EXPECT_NE(v.out.find(" s left)"), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("validate: PASS"), std::string::npos) << v.out;
  const Result b = onTerminal("bench --sizes 4096 --steps 20");
  EXPECT_EQ(b.status, 0) << b.out;
  EXPECT_NE(b.out.find("\r\033[Kbench 1/5 (20%"), std::string::npos) << b.out;
  EXPECT_NE(b.out.find(" s left)"), std::string::npos) << b.out;
  EXPECT_EQ(lava("validate --particles 2000 --steps 200").out.find('\r'), std::string::npos);
  EXPECT_EQ(lava("bench --sizes 4096 --steps 20 --backends gpu").out.find('\r'),
            std::string::npos);
}

TEST(Bench, WritesTheJsonItPromises) {
  const std::string json = scratch("bench.json");
  const Result r = lava("bench --sizes 4096,8192 --steps 20 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string text = readFile(json);
  for (const char* key :
       {"\"device\"", "\"results\"", "\"backend\": \"gpu\"", "\"backend\": \"cpu\"",
        "\"backend\": \"cpu-mt\"", "\"backend\": \"cpu-simd\"", "\"backend\": \"cpu-simd-mt\"",
        "\"particles\": 8192", "\"steps\": 20", "\"updates_per_second\"",
        "\"bytes_per_update\": 64", "\"roofline_fraction\"", "\"compute_fraction\"",
        "\"bound\": \"compute\""})
    EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '{'), 11) << text;  // 2 sizes x 5 backends
  EXPECT_NE(r.out.find("x compute"), std::string::npos) << r.out;
}

TEST(Environment, NoVulkanDriverIsOneClearLine) {
  const Result r = lava(
      "info", "env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("no Vulkan"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Environment, BadLavaDeviceIsAUsageError) {
  const Result r = lava("info", "env LAVA_DEVICE=seven ");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("LAVA_DEVICE"), std::string::npos) << r.err;
}

TEST(Environment, CpuBackendNeedsNoVulkan) {
  const Result r =
      lava("simulate --steps 100 --backend cpu",
           "env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json ");
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST(Render, VideoEncodesWithFfmpegOrSaysItIsMissing) {
  // Both branches in every run: ffmpeg missing from the PATH, and a stand-in ffmpeg that
  // records what it was given (no shell between: a quote in a path is just a character);
  // then the real one where it is installed (it is not a dependency).
  const std::string bin = scratch("fakebin"), calls = scratch("ffmpeg_args.txt");
  ASSERT_EQ(run("mkdir -p " + bin).status, 0);
  {
    std::ofstream fake(bin + "/ffmpeg");
    fake << "#!/bin/sh\n: > '" << calls << "'\nfor a in \"$@\"; do printf '%s\\n' \"$a\" >> '"
         << calls << "'; last=\"$a\"; done\nprintf 'mp4' > \"$last\"\n";
  }
  ASSERT_EQ(run("chmod +x " + bin + "/ffmpeg").status, 0);
  const std::string folder = scratch("it's frames"), clip = scratch("it's a clip.mp4");
  run("rm -rf '" + scratch("it") + "'*");
  // An earlier run's frames in the folder: only this run's 3 are encoded.
  ASSERT_EQ(lava("render --frames 6 --size 64x48 --out \"" + folder + "\"").status, 0);
  Result r = lava("render --frames 3 --size 65x49 --out \"" + folder + "\" --video \"" + clip + "\"",
                  "env PATH=" + bin + ":/usr/bin:/bin ");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string args = readFile(calls);
  EXPECT_NE(args.find(folder + "/frame_%05d.png\n"), std::string::npos) << args;
  EXPECT_NE(args.find("-frames:v\n3\n"), std::string::npos) << args;
  EXPECT_NE(args.find("pad=ceil(iw/2)*2:ceil(ih/2)*2"), std::string::npos) << args;
  EXPECT_EQ(readFile(clip), "mp4") << "the clip renamed into place";
  // No ffmpeg: a usage error naming --video, and no frames rendered for nothing.
  r = lava("render --frames 4 --size 64x48 --out " + scratch("noffmpeg") + " --video " +
               scratch("none.mp4"),
           "env PATH=/nonexistent ");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--video"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ffmpeg"), std::string::npos) << r.err;
  EXPECT_NE(access(scratch("noffmpeg").c_str(), F_OK), 0) << "no empty folder left";
  if (std::system("command -v ffmpeg >/dev/null 2>&1") == 0) {  // the real one, odd size
    const std::string real = scratch("real.mp4");
    r = lava("render --frames 3 --size 65x49 --out \"" + folder + "\" --video " + real);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_GT(readFile(real).size(), 100u);
  }
}

TEST(Render, AUsageErrorLeavesNoFolderBehind) {
  const std::string folder = scratch("never");
  run("rm -rf " + folder);
  EXPECT_EQ(lava("render --frames 2 --size 20000x20000 --out " + folder).status, 2);
  EXPECT_EQ(lava("render --frames 2 --fps 0 --out " + folder).status, 2);
  EXPECT_NE(access(folder.c_str(), F_OK), 0);
}

TEST(Help, VersionPrintsTheLibrarysVersion) {
  const Result r = lava("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("lava 0.", 0), 0u) << r.out;
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

// A number `lava info` prints after `label` (0 when it is missing).
unsigned long long infoNumber(const std::string& info, const std::string& label) {
  const size_t at = info.find(label);
  return at == std::string::npos ? 0 : std::strtoull(info.c_str() + at + label.size(), nullptr, 10);
}

TEST(Info, ListsTheDeviceAndTheLargestParticleCount) {
  const Result r = lava("info");
  EXPECT_EQ(r.status, 0) << r.err;
  // The selected device is one of those listed, by name.
  const size_t selected = r.out.find("selected device ");
  ASSERT_NE(selected, std::string::npos) << r.out;
  const std::string line = r.out.substr(selected, r.out.find('\n', selected) - selected);
  const std::string name = line.substr(line.find(": ") + 2);
  EXPECT_NE(r.out.find("] " + name), std::string::npos) << r.out;
  EXPECT_GT(infoNumber(r.out, "largest particle count"), 0u) << r.out;
  EXPECT_GT(infoNumber(r.out, "maxImageDimension2D"), 0u) << r.out;
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

TEST(Help, ExitsZeroAndListsCommands) {
  // The command list is exactly the commands; each command's help lists the scene keys it
  // takes (and every command takes --scene), with their defaults as typed, not as floats.
  const Result r = lava("--help");
  EXPECT_EQ(r.status, 0);
  const size_t list = r.out.find("Subcommands:");
  ASSERT_NE(list, std::string::npos) << r.out;
  std::istringstream lines(r.out.substr(list));
  std::string line;
  std::set<std::string> listed;
  std::getline(lines, line);
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string first;
    if (words >> first) listed.insert(first);
  }
  EXPECT_EQ(listed, (std::set<std::string>{"demo", "simulate", "validate", "render", "bench",
                                           "info", "study"}));
  for (const std::string& command : listed) {
    const Result h = lava(command + " --help");
    EXPECT_EQ(h.status, 0) << command;
    EXPECT_NE(h.out.find("--scene"), std::string::npos) << command;
    static const std::regex floatDigits(R"(\.[0-9]*0{5,}[1-9])");  // 0.001000000047
    EXPECT_FALSE(std::regex_search(h.out, floatDigits)) << command << " prints a float's digits";
  }
  EXPECT_NE(lava("simulate --help").out.find("--dt NUM"), std::string::npos);
  EXPECT_NE(lava("simulate --help").out.find("[0.001]"), std::string::npos);
}

}  // namespace
