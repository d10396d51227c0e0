// SPDX-License-Identifier: MIT
/// @file Fixed-size Takagi–Sugeno fuzzy neural network: forward pass and RT evaluation.
///
/// The network of Wei et al. 2019, §4, generalised to `kOutputs` outputs sharing one premise:
///   layer 2  μ_is = exp(−(x_i − c_is)²/σ_is²)            Gaussian memberships, x normalised
///   layer 3  α_j  = Π_i μ_i,s_i(j)                         rule firing (numbering: tsk_params.hpp)
///   layer 4  ᾱ_j  = α_j / Σ_k α_k                          normalisation
///   output   y_o  = Σ_j ᾱ_j (p_oj0 + Σ_i p_oj,1+i x_i)    first-order consequents
/// kOutputs = 1 is the paper's form (one network per error parameter); kOutputs = 4 evaluates
/// MPE, RPE, MAE and RAE from one premise in one pass.
///
/// How it is computed (same result, fewer operations, no NaN):
///  - memberships are shifted per input so the best set of each input is exactly 1
///    (`shifted_memberships`); the factor cancels in ᾱ because the rule product is separable.
///    Hence the best rule has α = 1, Σα ≥ 1, and the normalisation never divides by 0 or
///    produces 0/0, however far outside the sets an input lies;
///  - Σα = Π_i Σ_s μ_is (separable too), so the firing strengths need not be summed;
///  - the consequent sums t_ok = Σ_j α_j p_ojk are computed without forming α: the consequent
///    block of each output is a tensor [s_0][s_1]…[s_{n−1}][k] (rule numbering, input 0 most
///    significant), contracted with the memberships of input 0, then input 1, and so on. Each
///    stage is an element-wise weighted sum of kSets contiguous slices, which the compiler
///    vectorises without -ffast-math; then y_o = (t_o0 + Σ_i x_i t_o,1+i)/Σα.
///    `firing` builds the α_j explicitly (successive outer products) for inspection.
///
/// `TskEvaluator<Scalar, …>::forward` is the single implementation of the math: `evaluate`
/// runs it with double or float, training runs it with ceres::Jet (this header includes no
/// Ceres header; Jet's `exp` is found by argument-dependent lookup).
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/membership.hpp>
#include <cmmcomp/fuzzy/tsk_params.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>

namespace cmmcomp::fuzzy {

/// What `evaluate` does with an input outside its training range [lo, hi].
enum class DomainPolicy : std::uint8_t {
  kClamp,        ///< clamp the input to [lo, hi], compute, return Status::kOutsideDomain
  kExtrapolate,  ///< compute with the input as is, return Status::kOutsideDomain
  kReject,       ///< compute nothing, return Status::kOutsideDomainRejected
};

/// Forward pass of a network with `kInputs` inputs, `kSets` sets per input and `kOutputs`
/// outputs on normalised inputs. Stateless; all sizes compile-time; no allocation.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
class TskEvaluator {
 public:
  using Layout = TskLayout<kInputs, kSets, kOutputs>;
  static constexpr int kRules = Layout::kRules;            ///< kSets^kInputs
  static constexpr int kParamCount = Layout::kParamCount;  ///< size of the parameter block
  using Input = std::array<Scalar, kInputs>;               ///< normalised inputs
  using Output = std::array<Scalar, kOutputs>;
  using Firing = std::array<Scalar, kRules>;                           ///< one value per rule
  using Memberships = std::array<std::array<Scalar, kSets>, kInputs>;  ///< [input][set]

  /// Memberships of every input in every set, shifted per input so that the best set of each
  /// input is exactly 1 (`shifted_memberships`); returns Σ_j α_j = Π_i Σ_s μ_is, in
  /// [1, kRules]. RT-safe for floating-point Scalars. Preconditions: `params` holds kParamCount
  /// values (layout in tsk_params.hpp), widths > 0.
  static Scalar memberships(const Scalar* params, const Input& x, Memberships& mu) noexcept {
    Scalar total = Scalar(1.0);
    for (int i = 0; i < kInputs; ++i) {
      std::array<Scalar, kSets>& m = mu[static_cast<unsigned>(i)];
      shifted_memberships<Scalar, kSets>(x[static_cast<unsigned>(i)],
                                         params + Layout::centre_index(i, 0),
                                         params + Layout::width_index(i, 0),
                                         m.data());
      Scalar sum = m[0];
      for (int s = 1; s < kSets; ++s) sum += m[static_cast<unsigned>(s)];
      total *= sum;
    }
    return total;
  }

  /// Firing strengths α_j of every rule (numbering in tsk_params.hpp) for normalised inputs
  /// `x`, scaled so that the best rule has α = 1; returns Σ_j α_j, in [1, kRules]. Divide by it
  /// for the normalised strengths ᾱ_j. Not used by `forward`; for inspection and training.
  /// RT-safe for floating-point Scalars. Preconditions as `memberships`.
  static Scalar firing(const Scalar* params, const Input& x, Firing& alpha) noexcept {
    Memberships mu;
    const Scalar total = memberships(params, x, mu);
    // Outer products from the last input (least significant digit) to input 0: after input i,
    // alpha[0, n) holds the products over inputs i..kInputs-1, indexed by their digits.
    const std::array<Scalar, kSets>& last = mu[static_cast<unsigned>(kInputs - 1)];
    for (int s = 0; s < kSets; ++s)
      alpha[static_cast<unsigned>(s)] = last[static_cast<unsigned>(s)];
    int n = kSets;
    for (int i = kInputs - 2; i >= 0; --i) {
      const std::array<Scalar, kSets>& m = mu[static_cast<unsigned>(i)];
      for (int s = kSets - 1; s >= 1; --s) {  // blocks s >= 1 do not overlap alpha[0, n)
        const Scalar ms = m[static_cast<unsigned>(s)];
        Scalar* dst = alpha.data() + s * n;
        for (int k = 0; k < n; ++k) dst[k] = ms * alpha[static_cast<unsigned>(k)];
      }
      const Scalar m0 = m[0];
      for (int k = 0; k < n; ++k) alpha[static_cast<unsigned>(k)] *= m0;
      n *= kSets;
    }
    return total;
  }

  /// Network outputs `y` for normalised inputs `x` (Wei et al. 2019, §4, layers 1–4).
  /// RT-safe for floating-point Scalars: fixed loop counts, no branch on data, no allocation.
  /// The result is finite whenever the parameters and inputs are finite and the consequent sums
  /// do not overflow. Preconditions: `params` holds kParamCount values (layout in
  /// tsk_params.hpp), widths > 0.
  static void forward(const Scalar* params, const Input& x, Output& y) noexcept {
    constexpr int kTerms = Layout::kTerms;
    constexpr int kBlock = Layout::kConsequentBlock;
    // Contracted consequents after input 0, and after input 1 (later stages reuse the two).
    constexpr int kStage0 = kOutputs * (kBlock / kSets);
    constexpr int kStage1 = kInputs > 1 ? kStage0 / kSets : 1;

    Memberships mu;
    const Scalar total = memberships(params, x, mu);

    // Σ_j α_j p_ojk = Σ_s0 μ_0,s0 Σ_s1 μ_1,s1 … p_o,(s0 s1 …),k: contract the consequent tensor
    // [o][s0]…[s_{n-1}][k] one input at a time, most significant digit first. Each stage is an
    // element-wise weighted sum of kSets contiguous slices (vectorisable, no reduction chain).
    std::array<Scalar, kStage0> a;
    std::array<Scalar, kStage1> b;
    {
      constexpr int n = kBlock / kSets;  // slice length after input 0, per output
      const std::array<Scalar, kSets>& m = mu[0];
      for (int o = 0; o < kOutputs; ++o) {
        const Scalar* src = params + Layout::kConsequentsOffset + o * kBlock;
        Scalar* dst = a.data() + o * n;
        for (int e = 0; e < n; ++e) {
          Scalar sum = m[0] * src[e];
          for (int s = 1; s < kSets; ++s) sum += m[static_cast<unsigned>(s)] * src[s * n + e];
          dst[e] = sum;
        }
      }
    }
    const Scalar* src = a.data();
    int n = kBlock / kSets;
    for (int i = 1; i < kInputs; ++i) {
      const std::array<Scalar, kSets>& m = mu[static_cast<unsigned>(i)];
      Scalar* dst = (i % 2 == 1) ? b.data() : a.data();
      const int next = n / kSets;
      for (int o = 0; o < kOutputs; ++o) {
        const Scalar* so = src + o * n;
        Scalar* d = dst + o * next;
        for (int e = 0; e < next; ++e) {
          Scalar sum = m[0] * so[e];
          for (int s = 1; s < kSets; ++s) sum += m[static_cast<unsigned>(s)] * so[s * next + e];
          d[e] = sum;
        }
      }
      src = dst;
      n = next;
    }

    // src now holds t_ok = Σ_j α_j p_ojk, kTerms per output: y_o = (t_o0 + Σ_i x_i t_o,1+i)/Σα.
    const Scalar inv_total = Scalar(1.0) / total;
    for (int o = 0; o < kOutputs; ++o) {
      const Scalar* t = src + o * kTerms;
      Scalar sum = t[0];
      for (int i = 0; i < kInputs; ++i) sum += x[static_cast<unsigned>(i)] * t[i + 1];
      y[static_cast<unsigned>(o)] = sum * inv_total;
    }
  }
};

/// A published network: training ranges of the inputs plus the trained parameters. Plain value
/// type with std::array storage (no heap); copy it into place at model publication.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
struct TskModel {
  using Params = TskParams<Scalar, kInputs, kSets, kOutputs>;
  using Evaluator = TskEvaluator<Scalar, kInputs, kSets, kOutputs>;
  static constexpr int kRules = Params::kRules;            ///< kSets^kInputs
  static constexpr int kParamCount = Params::kParamCount;  ///< trained parameters
  using RawInput = std::array<double, kInputs>;            ///< inputs in their own units
  using RawOutput = std::array<double, kOutputs>;          ///< outputs (same units as trained)

  std::array<InputRange, kInputs> ranges{};  ///< training range of each input (raw units)
  Params params{};                           ///< trained parameters, normalised input units
};

/// The paper's network: inputs (PV, PD, AV, AD), 3 sets each, 81 rules, one output (429
/// parameters); one such network per error parameter.
using PaperNetwork = TskModel<double, 4, 3, 1>;
/// The paper's premise with one consequent block per error parameter, outputs in the order
/// (MPE, RPE, MAE, RAE), evaluated in one pass.
using PaperMultiNetwork = TskModel<double, 4, 3, 4>;

/// Evaluates `model` at raw (unnormalised) inputs `x` into `y`. RT-safe: no allocation, no
/// exception, bounded branch-light work. `Scalar` (double or float) is the precision of the
/// computation; `x` and `y` are double either way.
/// Inputs are normalised with the model's ranges; an input outside [lo, hi] is handled by
/// `policy`. `*outside_mask` (if given) gets bit i set when input i is outside its range; it is
/// written on every return except a non-finite input.
/// Returns:
///  - Status::kOk: all inputs inside their ranges; `y` written;
///  - Status::kOutsideDomain: some input outside, policy kClamp or kExtrapolate; `y` written;
///  - Status::kOutsideDomainRejected: some input outside, policy kReject; `y` untouched;
///  - Status::kInvalidInput: an input is NaN or ±inf, `policy` is not a DomainPolicy value, or
///    the result would not be finite (absurd parameters, or extrapolation far enough to
///    overflow); `y` untouched. A NaN or inf is never written to `y`.
/// Precondition: validate(model) holds (checked once at publication, not here).
template <typename Scalar, int kInputs, int kSets, int kOutputs>
[[nodiscard]] Status evaluate(
    const TskModel<Scalar, kInputs, kSets, kOutputs>& model,
    const typename TskModel<Scalar, kInputs, kSets, kOutputs>::RawInput& x,
    typename TskModel<Scalar, kInputs, kSets, kOutputs>::RawOutput& y,
    DomainPolicy policy,
    std::uint32_t* outside_mask = nullptr) noexcept {
  static_assert(std::is_floating_point_v<Scalar>, "evaluate runs with double or float");
  using Evaluator = TskEvaluator<Scalar, kInputs, kSets, kOutputs>;
  if (policy != DomainPolicy::kClamp && policy != DomainPolicy::kExtrapolate &&
      policy != DomainPolicy::kReject) {
    return Status::kInvalidInput;
  }
  const bool clamp = policy == DomainPolicy::kClamp;
  bool finite = true;
  std::uint32_t mask = 0;
  typename Evaluator::Input xn;
  for (int i = 0; i < kInputs; ++i) {
    const auto u = static_cast<unsigned>(i);
    const InputRange& r = model.ranges[u];
    const double v = x[u];
    finite = finite && std::isfinite(v);
    const bool below = v < r.lo;
    const bool above = v > r.hi;
    mask |= static_cast<std::uint32_t>(below || above) << u;
    const double inside = below ? r.lo : (above ? r.hi : v);
    xn[u] = static_cast<Scalar>(normalise(clamp ? inside : v, r));
  }
  if (!finite) return Status::kInvalidInput;
  if (outside_mask != nullptr) *outside_mask = mask;
  if (mask != 0 && policy == DomainPolicy::kReject) return Status::kOutsideDomainRejected;

  typename Evaluator::Output out;
  Evaluator::forward(model.params.data(), xn, out);
  for (int o = 0; o < kOutputs; ++o)
    finite = finite && std::isfinite(out[static_cast<unsigned>(o)]);
  if (!finite) return Status::kInvalidInput;
  for (int o = 0; o < kOutputs; ++o) {
    y[static_cast<unsigned>(o)] = static_cast<double>(out[static_cast<unsigned>(o)]);
  }
  return mask != 0 ? Status::kOutsideDomain : Status::kOk;
}

/// Checks that `model` may be published: every range finite with lo < hi (and hi − lo finite),
/// every parameter finite, every width > 0. Setup only (may allocate for `why`). On failure
/// returns false and, if `why` is given, stores the first problem found.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
bool validate(const TskModel<Scalar, kInputs, kSets, kOutputs>& model, std::string* why = nullptr) {
  static_assert(std::is_floating_point_v<Scalar>, "validate checks double or float models");
  using Layout = TskLayout<kInputs, kSets, kOutputs>;
  const auto fail = [why](std::string message) {
    if (why != nullptr) *why = std::move(message);
    return false;
  };
  for (int i = 0; i < kInputs; ++i) {
    const InputRange& r = model.ranges[static_cast<unsigned>(i)];
    if (!std::isfinite(r.lo) || !std::isfinite(r.hi) || !std::isfinite(r.hi - r.lo)) {
      return fail("range of input " + std::to_string(i) + " is not finite");
    }
    if (!(r.lo < r.hi)) {
      return fail("range of input " + std::to_string(i) + " has lo >= hi");
    }
  }
  for (int k = 0; k < Layout::kParamCount; ++k) {
    if (!std::isfinite(model.params.values[static_cast<unsigned>(k)])) {
      return fail("parameter " + std::to_string(k) + " is not finite");
    }
  }
  for (int i = 0; i < kInputs; ++i) {
    for (int s = 0; s < kSets; ++s) {
      if (!(model.params.width(i, s) > Scalar(0))) {
        return fail("width of set " + std::to_string(s) + " of input " + std::to_string(i) +
                    " is not positive");
      }
    }
  }
  return true;
}

}  // namespace cmmcomp::fuzzy
