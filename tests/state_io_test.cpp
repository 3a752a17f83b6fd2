// .npy / .csv output as docs/cli.md fixes it, and the checks that keep bad paths from losing work.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/files.h"
#include "expect_throw.h"
#include "host/output.h"
#include "lava/error.h"
#include "lava/validation.h"

namespace lava {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream s;
  s << file.rdbuf();
  return s.str();
}

using host::writeState;

std::vector<Particle> sample() {
  return {Particle{1.0f, 2.0f, 3.0f, 0.5f, 4.0f, 5.0f, 6.0f, 1.0f},
          Particle{0.0f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f, 0.0f, 0.0f}};
}

State sampleState() {
  State state;
  state.particles = sample();
  return state;
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "lava_" + std::to_string(getpid()) + "_" + name;
}

TEST(StateIo, NpyHasVersion1HeaderShapeAndRows) {
  const std::string path = tempPath("state.npy");
  writeState(path, sampleState());
  const std::string data = readFile(path);
  ASSERT_GT(data.size(), 10u);
  EXPECT_EQ(data.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const size_t headerLength = uint8_t(data[8]) | (uint8_t(data[9]) << 8);
  EXPECT_EQ((10 + headerLength) % 64, 0u);
  const std::string header = data.substr(10, headerLength);
  EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos);
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos);
  EXPECT_NE(header.find("'shape': (2, 7)"), std::string::npos);
  EXPECT_EQ(header.back(), '\n');
  ASSERT_EQ(data.size(), 10 + headerLength + 2 * 7 * sizeof(float));
  float rows[14];
  std::memcpy(rows, data.data() + 10 + headerLength, sizeof(rows));
  const float expected[14] = {1, 2, 3, 4, 5, 6, 0.5f, 0, 0, 0, 0, 0, 0, -1};
  for (int i = 0; i < 14; ++i) EXPECT_EQ(rows[i], expected[i]) << "value " << i;
  std::remove(path.c_str());
}

TEST(StateIo, CsvHasHeaderAndOneLinePerSlot) {
  const std::string path = tempPath("state.csv");
  writeState(path, sampleState());
  EXPECT_EQ(readFile(path), "px,py,pz,vx,vy,vz,age\n1,2,3,4,5,6,0.5\n0,0,0,0,0,0,-1\n");
  std::remove(path.c_str());
}

TEST(StateIo, AFlowAddsTheTemperatureColumn) {
  State state = sampleState();
  state.temperature = {1234.5f, 999.0f};  // the unborn slot's reads 0 whatever it holds
  state.crust = {0, 0};
  const std::string path = tempPath("flow.csv");
  writeState(path, state);
  EXPECT_EQ(readFile(path),
            "px,py,pz,vx,vy,vz,age,temperature\n1,2,3,4,5,6,0.5,1234.5\n0,0,0,0,0,0,-1,0\n");
  const std::string npy = tempPath("flow.npy");
  writeState(npy, state);
  const std::string data = readFile(npy);
  EXPECT_NE(data.find("'shape': (2, 8)"), std::string::npos);
  float last;
  std::memcpy(&last, data.data() + data.size() - 9 * sizeof(float), sizeof(float));
  EXPECT_EQ(last, 1234.5f) << "row 0's 8th column";
  std::remove(path.c_str());
  std::remove(npy.c_str());
}

std::vector<std::string> temporaries;  // what writeFileAtomically announced, in order

TEST(Files, AppearWholeWithTheUmasksPermissionsAndLeaveNoTemporary) {
  const std::string path = tempPath("atomic.txt");
  const mode_t previous = umask(027);
  common::writeFileAtomically(path, "first", [](const char* t) {
    temporaries.push_back(t ? t : "gone");
  });
  umask(previous);
  EXPECT_EQ(readFile(path), "first");
  struct stat info {};
  ASSERT_EQ(stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0640u);  // 0666 less the umask, not mkstemp's 0600
  ASSERT_EQ(temporaries.size(), 2u);
  EXPECT_EQ(temporaries[0].rfind(path + ".", 0), 0u) << temporaries[0];
  EXPECT_EQ(temporaries[1], "gone");
  EXPECT_NE(access(temporaries[0].c_str(), F_OK), 0) << "the temporary was left behind";

  common::writeFileAtomically(path, "second");  // replaces it whole
  EXPECT_EQ(readFile(path), "second");
  std::remove(path.c_str());

  test::expectThrowsWith<ResourceError>(
      [] { common::writeFileAtomically("/no/such/folder/file.txt", "x"); },
      "cannot write '/no/such/folder/file.txt'", "a file in a missing folder was written");
}

TEST(Compare, UlpDistance) {
  EXPECT_EQ(ulpDistance(1.0f, 1.0f), 0u);
  EXPECT_EQ(ulpDistance(1.0f, std::nextafter(1.0f, 2.0f)), 1u);
  // -0 and +0 differ in their bits: one step apart, so tolerance 0 tells them apart.
  EXPECT_EQ(ulpDistance(-0.0f, 0.0f), 1u);
  EXPECT_EQ(ulpDistance(std::nextafter(0.0f, -1.0f), std::nextafter(0.0f, 1.0f)), 3u);
  EXPECT_EQ(ulpDistance(1.0f, NAN), 0xffffffffu);
  EXPECT_EQ(ulpDistance(NAN, NAN), 0u);  // the same bits
  EXPECT_EQ(ulpDistance(NAN, -NAN), 0xffffffffu);
}

TEST(Compare, CountsEqualSlotsAndLargestDifferences) {
  std::vector<Particle> a = sample(), b = sample();
  b[0].py += 0.25f;
  b[0].vz = std::nextafter(b[0].vz, 10.0f);
  const Comparison c = compare(a, b);
  EXPECT_EQ(c.particles, 2u);
  EXPECT_EQ(c.equal, 1u);
  EXPECT_EQ(c.alive, 1u);
  EXPECT_EQ(c.maxDx, 0.25f);
  EXPECT_EQ(c.maxDv, std::nextafter(6.0f, 10.0f) - 6.0f);  // one ULP of 6: 2^-21
  EXPECT_EQ(c.maxUlp, ulpDistance(2.0f, 2.25f));
  ASSERT_TRUE(c.first);
  EXPECT_EQ(c.first->particle, 0u);
  EXPECT_EQ(c.first->field, 1u);  // py
  EXPECT_STREQ(fieldName(c.first->field), "py");
  EXPECT_EQ(c.first->subjectBits, 0x40000000u);    // 2.0f
  EXPECT_EQ(c.first->referenceBits, 0x40100000u);  // 2.25f
}

}  // namespace
}  // namespace lava
