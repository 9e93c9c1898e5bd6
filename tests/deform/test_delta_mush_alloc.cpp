// Delta Mush and Direct Delta Mush allocate nothing per frame: pose() from the second call on, counted
// by a malloc of this executable's own. Apart from test_delta_mush.cpp because what it can check
// depends on the build: every build compiles this file itself (tests/CMakeLists.txt, _per_build_files),
// and under a sanitizer, which owns malloc, the count is skipped.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cstddef>
#include <random>

#include "delta_mush_fixtures.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/direct_delta_mush.hpp"
#include "spinmotor/mesh/generators.hpp"

// Counting malloc (every operator new and every Eigen heap block goes through it with glibc), to check
// that pose() allocates nothing from the second call on. Not under a sanitizer, which owns malloc.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SPINMOTOR_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define SPINMOTOR_COUNT_MALLOC 0
#endif
#endif
#if !defined(SPINMOTOR_COUNT_MALLOC) && defined(__GLIBC__)
#define SPINMOTOR_COUNT_MALLOC 1
#endif
#ifndef SPINMOTOR_COUNT_MALLOC
#define SPINMOTOR_COUNT_MALLOC 0
#endif

#if SPINMOTOR_COUNT_MALLOC
#include <atomic>
namespace {
std::atomic<long> g_mallocs{0};
}
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* malloc(std::size_t n) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
#endif

namespace test_delta_mush_alloc {

using namespace spinmotor;
using namespace test_delta_mush_fixtures;
using Eigen::MatrixXd;

TEST_CASE("delta mush: pose allocates nothing from the second frame on (DM, DDM)", "[mush]") {
#if SPINMOTOR_COUNT_MALLOC
  const Mesh m = torus(2.0, 0.6, 40, 20);  // serial (below parallel::kMotorBlend): no OpenMP team to set up
  std::mt19937 rng(29);
  const auto bones = six_bones();
  const MatrixXd W = random_weights(m.V.rows(), 6, rng);
  const auto f1 = random_frames(bones, rng), f2 = random_frames(bones, rng);
  DeltaMushDeformer dm = DeltaMushDeformer::bind(m, bones, W, {});
  DeltaMushDeformer dm_dlb = DeltaMushDeformer::bind(m, bones, W, {.blend = SkinDeformer::Blend::DLB});
  DirectDeltaMushDeformer ddm = DirectDeltaMushDeformer::bind(m, bones, W, {});
  MatrixXd V1, V2, V3;
  dm.pose(f1, V1);
  dm_dlb.pose(f1, V2);
  ddm.pose(f1, V3);
  const long before = g_mallocs.load();
  dm.pose(f2, V1);
  dm_dlb.pose(f2, V2);
  ddm.pose(f2, V3);
  const long count = g_mallocs.load() - before;
  CHECK(count == 0);
  MatrixXd fresh;  // the counter does count: a new output buffer is one allocation
  const long before_fresh = g_mallocs.load();
  ddm.pose(f2, fresh);
  CHECK(g_mallocs.load() - before_fresh >= 1);
#else
  WARN("skipped: malloc is not counted under a sanitizer or without glibc");
#endif
}

}  // namespace test_delta_mush_alloc
