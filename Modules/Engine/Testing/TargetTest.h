// The engine's tests run once per dispatch target the library was built with
// and the CPU runs (hwy::SupportedAndGeneratedTargets()), each forced with
// hwy::SetSupportedTargetsForTest: derive a fixture from TargetTest and
// instantiate it with AVOS_ENGINE_TARGETS.
#ifndef avos_engine_TargetTest_h
#define avos_engine_TargetTest_h

#include "hwy/targets.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace avostest
{
class TargetTest : public ::testing::TestWithParam<int64_t>
{
protected:
  void SetUp() override { hwy::SetSupportedTargetsForTest(this->GetParam()); }
  void TearDown() override { hwy::SetSupportedTargetsForTest(0); }
};

inline std::string TargetName(const ::testing::TestParamInfo<int64_t>& info)
{
  return hwy::TargetName(info.param);
}
} // namespace avostest

#define AVOS_ENGINE_TARGETS(Fixture)                                                               \
  INSTANTIATE_TEST_SUITE_P(Engine, Fixture,                                                        \
    ::testing::ValuesIn(hwy::SupportedAndGeneratedTargets()), avostest::TargetName)

#endif
