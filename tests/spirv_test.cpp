// The simulation shader as compiled, read back with spirv-dis (docs/model.md, "The float
// rules"): every float add, subtract, multiply and divide carries NoContraction;
// no instruction a driver may compute inexactly (a dot product, an FMA, a transcendental)
// appears beyond the sphere collider's one square root and division; the float-controls
// execution modes each variant promises are there; and the structs laid out by std140 and
// std430 have exactly the offsets the C++ side writes.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdio>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "shared.h"

namespace lava::gpu {
namespace {

std::string disassemble(const std::string& stem) {
  const std::string command =
      "spirv-dis --raw-id " + std::string(LAVA_SPIRV_DIR) + "/" + stem + ".spv 2>&1";
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) out.push_back(line);
  return out;
}

struct Module {
  std::set<std::string> noContraction;                          // ids decorated NoContraction
  std::vector<std::pair<std::string, std::string>> arithmetic;  // (id, opcode)
  std::map<std::string, int> counts;                            // opcode or ExtInst name -> uses
  std::set<std::string> executionModes;               // "SignedZeroInfNanPreserve 32", ...
  std::map<std::string, std::map<int, int>> offsets;  // struct name -> member -> offset
};

Module parse(const std::string& stem) {
  const std::string text = disassemble(stem);
  EXPECT_NE(text.find("OpCapability Shader"), std::string::npos) << text.substr(0, 400);
  Module m;
  std::map<std::string, std::string> names;
  static const std::regex decorate(R"(OpDecorate (%\d+) NoContraction)");
  static const std::regex result(R"((%\d+) = (Op\w+))");
  static const std::regex extInst(R"(OpExtInst %\d+ %\d+ (\w+))");
  static const std::regex mode(R"(OpExecutionMode %\d+ (\w+ ?\d*))");
  static const std::regex name(R"re(OpName (%\d+) "(\w+)")re");
  static const std::regex member(R"(OpMemberDecorate (%\d+) (\d+) Offset (\d+))");
  std::vector<std::tuple<std::string, int, int>> members;
  for (const std::string& line : lines(text)) {
    std::smatch s;
    if (std::regex_search(line, s, decorate)) m.noContraction.insert(s[1]);
    if (std::regex_search(line, s, mode)) m.executionModes.insert(s[1]);
    if (std::regex_search(line, s, name)) names[s[1]] = s[2];
    if (std::regex_search(line, s, member))
      members.emplace_back(s[1], std::stoi(s[2]), std::stoi(s[3]));
    if (std::regex_search(line, s, result)) {
      const std::string op = s[2];
      ++m.counts[op];
      if (op == "OpFAdd" || op == "OpFSub" || op == "OpFMul" || op == "OpFDiv" ||
          op == "OpVectorTimesScalar")
        m.arithmetic.emplace_back(s[1], op);
      if (std::regex_search(line, s, extInst)) ++m.counts[s[1]];
    }
  }
  for (const auto& [id, index, offset] : members) m.offsets[names[id]][index] = offset;
  return m;
}

const char* kVariants[] = {"step_comp",        "step_signed_zero", "step_rte",
                            "step_plain",       "step_kernel_only",  // the ceiling: the same
                            "flow_comp",        "flow_signed_zero", "flow_rte",
                            "flow_plain"};  // the flow's passes, with the step's operations

TEST(Spirv, EveryFloatOperationOfTheStepAndTheFlowIsNoContraction) {
  for (const char* variant : kVariants) {
    const Module m = parse(variant);
    ASSERT_GT(m.arithmetic.size(), 100u) << variant << ": the step's arithmetic was not found";
    for (const auto& [id, op] : m.arithmetic)
      EXPECT_TRUE(m.noContraction.count(id))
          << variant << ": " << id << " = " << op << " may be contracted (not NoContraction)";
  }
}

TEST(Spirv, OnlyTheSphereUsesAnInexactOperation) {
  for (const char* variant : kVariants) {
    const Module m = parse(variant);
    for (const char* forbidden : {"OpDot",
                                  "OpMatrixTimesVector",
                                  "OpVectorTimesMatrix",
                                  "OpFMod",
                                  "OpFRem",
                                  "Fma",
                                  "InverseSqrt",
                                  "Length",
                                  "Normalize",
                                  "Distance",
                                  "Cross",
                                  "FMix",
                                  "Exp",
                                  "Exp2",
                                  "Log",
                                  "Log2",
                                  "Pow",
                                  "Sin",
                                  "Cos",
                                  "Tan",
                                  "Atan",
                                  "Atan2",
                                  "Ldexp",
                                  "Frexp"})
      EXPECT_EQ(m.counts.count(forbidden), 0u) << variant << " uses " << forbidden;
    EXPECT_EQ(m.counts.count("Sqrt") ? m.counts.at("Sqrt") : 0, 1) << variant;
    EXPECT_EQ(m.counts.count("OpFDiv") ? m.counts.at("OpFDiv") : 0, 3)
        << variant << ": the sphere's d / s, and nothing else";
  }
}

TEST(Spirv, FloatControlsAreDeclaredPerVariant) {
  const std::string zero = "SignedZeroInfNanPreserve 32", rte = "RoundingModeRTE 32";
  const std::pair<const char*, std::pair<bool, bool>> expected[] = {
      {"step_comp", {true, true}},
      {"step_signed_zero", {true, false}},
      {"step_rte", {false, true}},
      {"step_plain", {false, false}},
      {"flow_comp", {true, true}},
      {"flow_signed_zero", {true, false}},
      {"flow_rte", {false, true}},
      {"flow_plain", {false, false}}};
  for (const auto& [variant, modes] : expected) {
    const Module m = parse(variant);
    EXPECT_EQ(m.executionModes.count(zero), modes.first ? 1u : 0u) << variant;
    EXPECT_EQ(m.executionModes.count(rte), modes.second ? 1u : 0u) << variant;
  }
}

// The offsets the compiler gave each member against offsetof on the C++ side.
TEST(Spirv, StructLayoutsMatchTheCppSide) {
  const Module m = parse("step_comp");
  const std::map<std::string, std::vector<size_t>> expected = {
      {"SceneParams",
       {offsetof(SceneParams, world), offsetof(SceneParams, wind), offsetof(SceneParams, emitters),
        offsetof(SceneParams, forces), offsetof(SceneParams, colliders)}},
      {"EmitterParams",
       {offsetof(EmitterParams, position), offsetof(EmitterParams, velocity),
        offsetof(EmitterParams, spread), offsetof(EmitterParams, size),
        offsetof(EmitterParams, constants), offsetof(EmitterParams, ring)}},
      {"ForceParams",
       {offsetof(ForceParams, position), offsetof(ForceParams, axis), offsetof(ForceParams, kind)}},
      {"ColliderParams",
       {offsetof(ColliderParams, position), offsetof(ColliderParams, shape),
        offsetof(ColliderParams, cone), offsetof(ColliderParams, material),
        offsetof(ColliderParams, kind)}},
      {"StepParams", {offsetof(StepParams, run), offsetof(StepParams, chunk)}},
      {"EmitEntry", {offsetof(EmitEntry, ring), offsetof(EmitEntry, sums)}},
      {"Particle", {offsetof(Particle, px), offsetof(Particle, vx)}},
  };
  for (const auto& [name, members] : expected) {
    auto it = m.offsets.find(name);
    ASSERT_NE(it, m.offsets.end()) << name << " not in the SPIR-V";
    ASSERT_EQ(it->second.size(), members.size()) << name;
    for (size_t i = 0; i < members.size(); ++i)
      EXPECT_EQ(size_t(it->second.at(int(i))), members[i]) << name << " member " << i;
  }
}

}  // namespace
}  // namespace lava::gpu
