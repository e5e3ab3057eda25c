#pragma once
// Shared Vulkan context for GPU tests, with validation on, and the VulkanTest fixture that skips
// when no device exists and fails any test during which the validation layers said something.
#include <shapespline/vk/context.h>

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace shapespline::test {

// One Context per test process, created on first use with validation ON and its pipeline cache in
// the build tree (unless $SHAPESPLINE_CACHE_DIR is set). nullptr only when there is no Vulkan device
// (noDeviceReason() says why); any other failure throws.
std::shared_ptr<vk::Context> testContext();
const std::string& noDeviceReason();

// "[error] VUID-...: text" per line.
std::string formatValidationMessages(const std::vector<vk::ValidationMessage>& messages);

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override;     // GTEST_SKIP when no device; clears validation messages
  void TearDown() override;  // fails the test if any validation message was recorded

  vk::Context& ctx() { return *ctx_; }
  std::shared_ptr<vk::Context> ctx_;
};

}  // namespace shapespline::test
