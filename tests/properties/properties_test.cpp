// The detector's properties (issue 4) on generated scenes, one test per property. Each runs
// a bounded number of cases from a fixed seed unless RC_PARAMS sets max_success or seed
// (scripts/property-campaign.sh runs long campaigns). A failure prints the
// shrunk scene spec: store it as fixtures/regressions/<name>.json (regressions_test.cpp).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include "generators.h"
#include "scene_case.h"

namespace mbest::properties {
namespace {

constexpr std::uint64_t kCiSeed = 20261122;

// Runs check() on specs drawn from `gen`: `cases` passing cases unless RC_PARAMS sets
// max_success, from seed kCiSeed unless RC_PARAMS sets seed. Prints the counts of passed and discarded cases and the time taken.
void run_property(const rc::Gen<SceneSpec>& gen, int cases) {
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  rc::detail::TestParams params = rc::detail::configuration().testParams;
  const char* env = std::getenv("RC_PARAMS");
  if (env == nullptr || std::string(env).find("max_success") == std::string::npos) {
    params.maxSuccess = cases;
  }
  // CI runs the same cases every time; scripts/property-campaign.sh sets seeds of its own.
  if (env == nullptr || std::string(env).find("seed") == std::string::npos) params.seed = kCiSeed;
  rc::detail::TestMetadata metadata;
  metadata.id = std::string(t->test_suite_name()) + "/" + t->name();
  metadata.description = t->name();
  auto discarded = std::make_shared<std::atomic<int>>(0);
  const auto start = std::chrono::steady_clock::now();
  const auto result = rc::detail::checkTestable(
      [gen, discarded] {
        const SceneSpec spec = *gen;
        const Verdict v = check(spec);
        if (!v.discard.empty()) {
          ++*discarded;
          RC_DISCARD(v.discard);
        }
        if (!v.failures.empty()) RC_FAIL(v.describe());
      },
      metadata, params);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream counts;
  counts << "[property] " << t->name() << ": ";
  if (result.template is<rc::detail::SuccessResult>()) {
    counts << result.template get<rc::detail::SuccessResult>().numSuccess << " cases passed";
  } else if (result.template is<rc::detail::FailureResult>()) {
    counts << result.template get<rc::detail::FailureResult>().numSuccess
           << " cases passed before a failure";
  }
  counts << ", " << discarded->load() << " scenes discarded (premise not met), seed "
         << params.seed << ", " << seconds << " s";
  std::cout << counts.str() << std::endl;
  if (!result.template is<rc::detail::SuccessResult>()) {
    std::ostringstream ss;
    rc::detail::printResultMessage(result, ss);
    FAIL() << ss.str()
           << "\nStore the shrunk spec above in fixtures/regressions/<name>.json to replay it.";
  }
}

TEST(Properties, TwoRodsCrossingOnce) { run_property(gen::two_rods(), 40); }
TEST(Properties, OneRodEndToEnd) { run_property(gen::one_rod(), 40); }
TEST(Properties, Equivariance) { run_property(gen::equivariance(), 30); }
TEST(Properties, AnySceneWellFormed) { run_property(gen::any_scene(), 50); }
TEST(Properties, RingIsOneClosedDlo) { run_property(gen::ring(), 30); }
TEST(Properties, TriplePointThreeDlos) { run_property(gen::triple(), 30); }
TEST(Properties, LoopIsOneDloCrossingItself) { run_property(gen::loop(), 30); }

}  // namespace
}  // namespace mbest::properties
