#include "support/vk_fixture.h"

#include <shapespline/vk/error.h>

#include <cstdlib>
#include <mutex>

namespace shapespline::test {

namespace {

struct SharedContext {
  std::once_flag once;
  std::shared_ptr<vk::Context> ctx;
  std::string reason;
};

SharedContext& shared() {
  static SharedContext s;
  return s;
}

}  // namespace

std::shared_ptr<vk::Context> testContext() {
  SharedContext& s = shared();
  // call_once: a throw (a real failure, not "no device") leaves it un-run, so the next test retries
  // and fails with the same message instead of silently skipping.
  std::call_once(s.once, [&] {
    vk::ContextOptions options;
    options.validation = true;
    options.appName = "shapespline-tests";
    const char* cacheEnv = std::getenv("SHAPESPLINE_CACHE_DIR");
    if (cacheEnv == nullptr || *cacheEnv == '\0') {
      options.cacheDir = SHAPESPLINE_BINARY_DIR "/test-pipeline-cache";  // keep ~/.cache out of tests
    }
    try {
      s.ctx = vk::Context::create(options);
    } catch (const vk::NoDeviceError& e) {
      s.reason = e.what();
    }
  });
  return s.ctx;
}

const std::string& noDeviceReason() {
  testContext();
  return shared().reason;
}

std::string formatValidationMessages(const std::vector<vk::ValidationMessage>& messages) {
  std::string text;
  for (const vk::ValidationMessage& m : messages) {
    text += m.severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "[error] " : "[warning] ";
    text += m.id + ": " + m.text + "\n";
  }
  return text;
}

void VulkanTest::SetUp() {
  ctx_ = testContext();
  if (!ctx_) GTEST_SKIP() << "no Vulkan device: " << noDeviceReason();
  ctx_->clearValidationMessages();
}

void VulkanTest::TearDown() {
  if (!ctx_) return;
  const auto messages = ctx_->validationMessages();
  if (!messages.empty()) {
    ADD_FAILURE() << messages.size() << " Vulkan validation message(s) during this test:\n"
                  << formatValidationMessages(messages);
  }
  ctx_->clearValidationMessages();
}

}  // namespace shapespline::test
