// SPDX-License-Identifier: MIT
/// @file The RT evaluation of the T-S network never allocates (operator new or malloc family).
#include <gtest/gtest.h>

#include <array>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstdlib>
#include <random>
#include <vector>

#include "support/allocation_counter.hpp"
#include "support/test_seed.hpp"

namespace cmmcomp::fuzzy {
namespace {

// Keeps the compiler from eliding an allocation whose result is otherwise unused.
void escape(const void* p) { asm volatile("" : : "g"(p) : "memory"); }

TskModel<double, 4, 3, 4> random_model(std::mt19937_64& rng) {
  TskModel<double, 4, 3, 4> m;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto& r : m.ranges) r = InputRange{0.0, 1.0 + unit(rng)};
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = 0.5 * s;
      m.params.width(i, s) = 0.2 + 0.3 * unit(rng);
    }
  }
  for (int k = TskModel<double, 4, 3, 4>::Params::kConsequentsOffset;
       k < TskModel<double, 4, 3, 4>::kParamCount;
       ++k) {
    m.params.values[static_cast<unsigned>(k)] = unit(rng) - 0.5;
  }
  return m;
}

TEST(AllocationCounter, CountsVectorAndMallocAllocations) {  // the positive control
  test::AllocationCounter allocs;
  {
    std::vector<double> v(100, 1.0);
    escape(v.data());
  }
  EXPECT_EQ(allocs.count(), 1u);
  void* p = std::malloc(64);
  escape(p);
  p = std::realloc(p, 128);
  escape(p);
  std::free(p);
  void* q = std::calloc(4, 16);
  escape(q);
  std::free(q);
  EXPECT_EQ(allocs.count(), 4u);
  auto* aligned = new (std::align_val_t{64}) double[3];
  escape(aligned);
  operator delete[](aligned, std::align_val_t{64});
  EXPECT_EQ(allocs.count(), 5u);
}

TEST(AllocationCounter, CountsNothingOutsideItsScope) {
  std::size_t inside = 0;
  {
    test::AllocationCounter allocs;
    inside = allocs.count();
  }
  std::vector<int> v(10);
  escape(v.data());
  EXPECT_EQ(inside, 0u);
}

TEST(TskEvaluatorRt, EvaluateDoesNotAllocate) {
  std::mt19937_64 rng(test::seed());
  const TskModel<double, 4, 3, 4> model = random_model(rng);
  TskModel<float, 4, 3, 4> model_f;
  model_f.ranges = model.ranges;
  for (std::size_t k = 0; k < model.params.values.size(); ++k) {
    model_f.params.values[k] = static_cast<float>(model.params.values[k]);
  }
  std::vector<std::array<double, 4>> xs(10000);         // prepared before counting
  std::uniform_real_distribution<double> u(-0.5, 2.5);  // inside and outside the ranges
  for (auto& x : xs) {
    for (auto& v : x) v = u(rng);
  }
  std::array<double, 4> y{};
  std::size_t failures = 0;
  std::size_t outside = 0;
  std::uint32_t mask = 0;
  test::AllocationCounter allocs;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const DomainPolicy policy = static_cast<DomainPolicy>(k % 3);
    const Status s = evaluate(model, xs[k], y, policy, &mask);
    failures += (s == Status::kInvalidInput) ? 1u : 0u;
    outside += mask != 0 ? 1u : 0u;
    const Status sf = evaluate(model_f, xs[k], y, DomainPolicy::kClamp);
    failures += ok(sf) ? 0u : 1u;
  }
  const std::size_t count = allocs.count();
  EXPECT_EQ(count, 0u);
  EXPECT_EQ(failures, 0u);
  EXPECT_GT(outside, 0u);
}

}  // namespace
}  // namespace cmmcomp::fuzzy
