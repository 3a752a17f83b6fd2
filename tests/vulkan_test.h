// A fixture for tests that touch Vulkan: a context with the validation layer and its
// synchronization validation on; any message the layer reports fails the test.
#pragma once
#include <gtest/gtest.h>

#include <memory>

#include "context.h"

namespace lava::test {

inline ContextOptions validatedOptions() {
  ContextOptions options;
  options.validation = true;
  options.syncValidation = true;
  options.hostImport = true;
  return options;
}

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<Context>(validatedOptions()); }
  void TearDown() override {
    for (const std::string& message : context_->takeValidationMessages())
      ADD_FAILURE() << "validation: " << message;
  }
  Context& context() { return *context_; }

 private:
  std::unique_ptr<Context> context_;
};

}  // namespace lava::test
