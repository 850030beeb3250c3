// choose_collision_backend: --collision cpu never needs EGL; gpu takes any context (llvmpipe
// included: that is how CI runs the GPU path) and is an error naming the EGL problem without
// one; auto takes a hardware GPU only, saying "llvmpipe (software)" when it passes one over.
#include "gpu/collision_backend.h"

#include <gtest/gtest.h>

namespace sweepd::gpu {
namespace {

const EglDevice kLlvmpipe{"llvmpipe (LLVM 15.0.6, 256 bits)", true, ""};
const EglDevice kHardware{"NVIDIA H100 80GB HBM3/PCIe/SSE2", false, ""};
const EglDevice kNoEgl{"", false, "no headless OpenGL 4.5 core context through EGL: no display"};

TEST(CollisionBackend, CpuIsChosenWithoutLookingAtEgl) {
  for (const EglDevice& device : {kLlvmpipe, kHardware, kNoEgl})
    EXPECT_EQ(choose_collision_backend(CollisionChoice::kCpu, device).backend,
              CollisionBackend::kCpu);
}

TEST(CollisionBackend, GpuTakesAnyContextAndWithoutOneIsAnErrorNamingIt) {
  const CollisionBackendDecision on_llvmpipe =
      choose_collision_backend(CollisionChoice::kGpu, kLlvmpipe);
  EXPECT_EQ(on_llvmpipe.backend, CollisionBackend::kGpu);
  EXPECT_NE(on_llvmpipe.reason.find("llvmpipe (software)"), std::string::npos)
      << on_llvmpipe.reason;
  EXPECT_EQ(choose_collision_backend(CollisionChoice::kGpu, kHardware).backend,
            CollisionBackend::kGpu);
  try {
    choose_collision_backend(CollisionChoice::kGpu, kNoEgl);
    FAIL() << "no error without EGL";
  } catch (const CollisionBackendError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("--collision gpu: no usable EGL context"), std::string::npos) << message;
    EXPECT_NE(message.find(kNoEgl.failure), std::string::npos) << message;
  }
}

TEST(CollisionBackend, AutoTakesAHardwareGpuOnlyAndSaysWhy) {
  const CollisionBackendDecision hardware =
      choose_collision_backend(CollisionChoice::kAuto, kHardware);
  EXPECT_EQ(hardware.backend, CollisionBackend::kGpu);
  EXPECT_NE(hardware.reason.find("NVIDIA H100"), std::string::npos) << hardware.reason;
  const CollisionBackendDecision software =
      choose_collision_backend(CollisionChoice::kAuto, kLlvmpipe);
  EXPECT_EQ(software.backend, CollisionBackend::kCpu);
  EXPECT_NE(software.reason.find("llvmpipe (software)"), std::string::npos) << software.reason;
  const CollisionBackendDecision none = choose_collision_backend(CollisionChoice::kAuto, kNoEgl);
  EXPECT_EQ(none.backend, CollisionBackend::kCpu);
  EXPECT_NE(none.reason.find("no usable EGL context"), std::string::npos) << none.reason;
}

TEST(CollisionBackend, SoftwareRenderersAreKnownByNameWhereEglDoesNotSay) {
  EXPECT_TRUE(is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)", false));
  EXPECT_TRUE(is_software_renderer("softpipe", false));
  EXPECT_TRUE(is_software_renderer("anything", true));
  EXPECT_FALSE(is_software_renderer("NVIDIA H100 80GB HBM3/PCIe/SSE2", false));
}

TEST(CollisionBackend, ChoicesParseFromTheirNamesOnly) {
  for (const CollisionChoice choice :
       {CollisionChoice::kAuto, CollisionChoice::kGpu, CollisionChoice::kCpu})
    EXPECT_EQ(parse_collision_choice(to_string(choice)), choice);
  EXPECT_EQ(parse_collision_choice("GPU"), std::nullopt);
  EXPECT_EQ(parse_collision_choice(""), std::nullopt);
}

}  // namespace
}  // namespace sweepd::gpu
