// Interrupted and concurrent runs: Ctrl-C and SIGTERM write the checkpoint or nothing, two
// writers of one file leave one whole output, the progress line on a terminal.
#include <string>
#include <vector>

#include "cli_test.h"

namespace {
using namespace cli;

// A child process running build/lava with `args`, its `stream` (stdout or stderr) written to
// `path`: its id, or -1 when it could not be started.
pid_t startLava(FILE* stream, const std::string& path, const std::vector<std::string>& args) {
  // Made before the fork: the child only reopens its stream and runs the program.
  std::vector<char*> argv{const_cast<char*>(LAVA_EXE)};
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  const pid_t child = fork();
  if (child == 0) {
    freopen(path.c_str(), "w", stream);
    execv(LAVA_EXE, argv.data());
    _exit(127);
  }
  return child;
}

// Sends Ctrl-C's SIGINT to `child` and waits for it: its wait status.
int interrupt(pid_t child) {
  kill(child, SIGINT);
  int raw = 0;
  waitpid(child, &raw, 0);
  return raw;
}

TEST(Checkpoint, SigintWritesItAndTheResumedRunMatchesTheUninterruptedOne) {
  // A long run on the CPU, interrupted mid-way: exit 130 saying after how many steps, the
  // checkpoint written at a step boundary; resumed for 500 more steps it matches a run that
  // took those steps in one go.
  const std::string ck = scratch("interrupted.npz"), log = scratch("interrupted.log");
  std::remove(ck.c_str());
  const pid_t child = startLava(
      stdout, log,
      {"simulate", "--particles", "20000", "--rate", "5000", "--backend", "cpu", "--threads", "1",
       "--steps", "1000000", "--checkpoint", ck, "--checkpoint-every", "1000"});
  ASSERT_GE(child, 0);
  // The first periodic checkpoint says the run is under way (its handlers installed).
  for (int i = 0; i < 600 && access(ck.c_str(), F_OK) != 0; ++i) usleep(50 * 1000);
  usleep(300 * 1000);
  const int raw = interrupt(child);
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
  const pid_t child = startLava(stderr, err,
                                {"simulate", "--particles", "20000", "--backend", "cpu",
                                 "--threads", "1", "--steps", "1000000", "--out", out});
  ASSERT_GE(child, 0);
  usleep(800 * 1000);
  const int raw = interrupt(child);
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

}  // namespace
