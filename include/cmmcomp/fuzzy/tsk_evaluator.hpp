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
/// How it is computed (same result, fewer operations, no NaN, vectorisable without -ffast-math):
///  - the exponents of all memberships are formed set by set, all inputs at once (centres and
///    widths are stored set-major, tsk_params.hpp); each input's exponents are shifted by their
///    maximum, so that its best set gets exactly 1. The factor cancels in ᾱ because the rule
///    product is separable. Hence the best rule has α = 1, Σα ≥ 1, and the normalisation never
///    divides by 0 or produces 0/0, however far outside the sets an input lies;
///  - exp is `exp_nonpositive` (exp_nonpositive.hpp): vectorisable, within 2 ulp;
///  - Σα = Π_i Σ_s μ_is (separable too), so the firing strengths need not be summed;
///  - the consequent sums t_ok = Σ_j α_j p_jok take one of two routes, chosen at compile time
///    by the size of one rule's consequent block, kOutputs·(kInputs+1) (tsk_params.hpp stores
///    them rule-major, so that block is contiguous):
///    - a multiple of 4 (the paper's 4-output network: 20): `sum_by_rule`. α is built as
///      α_j = A_p·B_q for rule j = p·|B| + q (A over the first half of the inputs, the rule
///      number's high digits, B over the rest), then each rule adds α_j times its block into two
///      accumulators (even and odd rules, to halve the add chains). That is the minimum work for
///      dense consequents: each is read once and used in one multiply-add, 1620 for the paper's;
///    - otherwise (one output: 5 values a rule, which would not fill vectors): `sum_by_contraction`
///      contracts the consequent tensor [s_0]…[s_{n−1}][block] with the memberships of one
///      input at a time, each stage an element-wise weighted sum of contiguous slices;
///  - then y_o = (t_o0 + Σ_i x_i t_o,1+i)/Σα.
/// The order of every floating-point operation is fixed by the source (no reductions left to the
/// compiler), so scalar and SIMD builds of any width give the same bits when FMA contraction is
/// off: cmmcomp's own builds turn it off, and a consumer links cmmcomp::strict_fp to do the
/// same (cmmcomp::core sets no flags).
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
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace cmmcomp::fuzzy {

/// What `evaluate` does with an input outside its training range [lo, hi].
enum class DomainPolicy : std::uint8_t {
  kClamp,        ///< clamp the input to [lo, hi], compute, return Status::kOutsideDomain
  kExtrapolate,  ///< compute with the input as is, return Status::kOutsideDomain
  kReject,       ///< compute nothing, return Status::kOutsideDomainRejected
};

/// Every policy, in declaration order.
inline constexpr DomainPolicy kDomainPolicies[] = {
    DomainPolicy::kClamp, DomainPolicy::kExtrapolate, DomainPolicy::kReject};

/// The policy's name as users write it: "clamp", "extrapolate", "reject".
constexpr const char* to_string(DomainPolicy policy) noexcept {
  switch (policy) {
    case DomainPolicy::kClamp:
      return "clamp";
    case DomainPolicy::kExtrapolate:
      return "extrapolate";
    case DomainPolicy::kReject:
      return "reject";
  }
  return "unknown";
}

/// Parses a policy name (to_string's spelling) into `*policy`. Returns false, leaving `*policy`
/// as it was, for any other text. Every tool parses `--outside-domain` with this.
constexpr bool parse_domain_policy(std::string_view text, DomainPolicy* policy) noexcept {
  for (const DomainPolicy p : kDomainPolicies) {
    if (text == to_string(p)) {
      *policy = p;
      return true;
    }
  }
  return false;
}

/// Loop nest of the consequent sums of a multi-output network (TskEvaluator::forward). Both give
/// the same bits; they differ in speed by target.
enum class SumRoute : std::uint8_t {
  kByRule,   ///< rule by rule over the whole block: SIMD hosts (SSE2, AVX2, NEON)
  kChunked,  ///< 4 block values at a time over all rules: scalar FPUs (Cortex-M)
};

/// The route `forward` takes by default: kChunked on an M-profile Arm core (or when
/// CMMCOMP_FUZZY_CHUNKED_SUMS is defined to 1), kByRule elsewhere.
#if !defined(CMMCOMP_FUZZY_CHUNKED_SUMS)
#if defined(__ARM_ARCH_PROFILE) && __ARM_ARCH_PROFILE == 'M'
#define CMMCOMP_FUZZY_CHUNKED_SUMS 1
#else
#define CMMCOMP_FUZZY_CHUNKED_SUMS 0
#endif
#endif
inline constexpr SumRoute kDefaultSumRoute =
    CMMCOMP_FUZZY_CHUNKED_SUMS ? SumRoute::kChunked : SumRoute::kByRule;

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
  /// input is exactly 1: μ_is = exp(e_is − max_t e_it) with e_is = −((x_i − c_is)/σ_is)²;
  /// returns Σ_j α_j = Π_i Σ_s μ_is, in [1, kRules]. Every value is in [0, 1], never NaN, even
  /// when every plain membership of an input underflows (an input far outside its sets). For
  /// inspection and tests; `forward` computes the same values in its own (set-major) order.
  /// RT-safe for floating-point Scalars. Preconditions: `params` holds kParamCount values
  /// (layout in tsk_params.hpp), widths > 0.
  static Scalar memberships(const Scalar* params, const Input& x, Memberships& mu) noexcept {
    SetMajor m;
    const Scalar total = premise(params, x, m);
    for (int i = 0; i < kInputs; ++i) {
      for (int s = 0; s < kSets; ++s) mu[u(i)][u(s)] = m[u(s)][u(i)];
    }
    return total;
  }

  /// Firing strengths α_j of every rule (numbering in tsk_params.hpp) for normalised inputs
  /// `x`, scaled so that the best rule has α = 1; returns Σ_j α_j, in [1, kRules]. Divide by it
  /// for the normalised strengths ᾱ_j. Used by training for its design matrix and by tests.
  /// RT-safe for floating-point Scalars. Preconditions as `memberships`.
  static Scalar firing(const Scalar* params, const Input& x, Firing& alpha) noexcept {
    SetMajor m;
    const Scalar total = premise(params, x, m);
    outer_product<0, kInputs>(m, alpha);
    return total;
  }

  /// Network outputs `y` for normalised inputs `x` (Wei et al. 2019, §4, layers 1–4).
  /// RT-safe for floating-point Scalars: fixed loop counts, no branch on data, no allocation.
  /// The result is finite whenever the parameters and inputs are finite and the consequent sums
  /// do not overflow. Preconditions: `params` holds kParamCount values (layout in
  /// tsk_params.hpp), widths > 0.
  /// `kRoute` picks the loop nest of the consequent sums (SumRoute); every route performs the
  /// same operations in the same order, so the result has the same bits whichever runs.
  template <SumRoute kRoute = kDefaultSumRoute>
  static void forward(const Scalar* params, const Input& x, Output& y) noexcept {
    constexpr int kTerms = Layout::kTerms;
    SetMajor m;
    const Scalar total = premise(params, x, m);
    Block t;  // t_ok = Σ_j α_j p_jok
    if constexpr (kBlock % 4 == 0 && kRoute == SumRoute::kChunked) {
      sum_by_rule_chunked(params + Layout::kConsequentsOffset, m, t);
    } else if constexpr (kBlock % 4 == 0) {
      sum_by_rule(params + Layout::kConsequentsOffset, m, t);
    } else {
      sum_by_contraction(params + Layout::kConsequentsOffset, m, t);
    }
    const Scalar inv_total = Scalar(1.0) / total;
    for (int o = 0; o < kOutputs; ++o) {
      const int first = o * kTerms;
      Scalar sum = t[u(first)];
      for (int i = 0; i < kInputs; ++i) sum += x[u(i)] * t[u(first + 1 + i)];
      y[u(o)] = sum * inv_total;
    }
  }

 private:
  /// Memberships in the evaluator's order, [set][input]: one set of every input together.
  using SetMajor = std::array<std::array<Scalar, kInputs>, kSets>;
  /// The rule number's digits split in two: inputs [0, kHead) give the factor index p of α
  /// (high digits), inputs [kHead, kInputs) its column q (low digits); rule j = p·kCols + q.
  static constexpr int kHead = kInputs / 2;
  static constexpr int kRows = detail::checked_pow(kSets, kHead);
  static constexpr int kCols = detail::checked_pow(kSets, kInputs - kHead);
  /// Consequents of one rule, every output: kOutputs·(kInputs + 1), contiguous.
  static constexpr int kBlock = Layout::kRuleBlock;
  using Block = std::array<Scalar, kBlock>;

  static constexpr unsigned u(int i) noexcept { return static_cast<unsigned>(i); }

  /// Shifted memberships m[s][i] (see `memberships`) and Σα. Each loop runs over whole
  /// set-major rows, so it vectorises across the inputs.
  static Scalar premise(const Scalar* params, const Input& x, SetMajor& m) noexcept {
    const Scalar* centres = params + Layout::kCentresOffset;
    const Scalar* widths = params + Layout::kWidthsOffset;
    SetMajor e;
    for (int s = 0; s < kSets; ++s) {
      for (int i = 0; i < kInputs; ++i) {
        const int k = s * kInputs + i;
        e[u(s)][u(i)] = gaussian_exponent(x[u(i)], centres[k], widths[k]);
      }
    }
    Input top = e[0];
    for (int s = 1; s < kSets; ++s) {
      for (int i = 0; i < kInputs; ++i) top[u(i)] = detail::max_of(top[u(i)], e[u(s)][u(i)]);
    }
    for (int s = 0; s < kSets; ++s) {
      for (int i = 0; i < kInputs; ++i) {
        m[u(s)][u(i)] = membership_exp(Scalar(e[u(s)][u(i)] - top[u(i)]));
      }
    }
    Input sum = m[0];
    for (int s = 1; s < kSets; ++s) {
      for (int i = 0; i < kInputs; ++i) sum[u(i)] += m[u(s)][u(i)];
    }
    Scalar total = sum[0];
    for (int i = 1; i < kInputs; ++i) total *= sum[u(i)];
    return total;
  }

  /// out[0, kSets^(kLast − kFirst)) = the products Π_{kFirst <= i < kLast} m[s_i][i], indexed by
  /// the digits s_kFirst … s_{kLast−1} (s_kFirst most significant); 1 for an empty range. Each
  /// product is formed on its own (compile-time digits once unrolled), so no value is stored and
  /// read back while building.
  template <int kFirst, int kLast>
  static void outer_product(
      const SetMajor& m,
      std::array<Scalar, static_cast<std::size_t>(detail::checked_pow(kSets, kLast - kFirst))>&
          out) noexcept {
    if constexpr (kFirst == kLast) {
      out[0] = Scalar(1.0);
    } else {
      for (std::size_t k = 0; k < out.size(); ++k) {
        int code = static_cast<int>(k);
        Scalar product = m[u(code % kSets)][u(kLast - 1)];
        for (int i = kLast - 2; i >= kFirst; --i) {
          code /= kSets;
          product *= m[u(code % kSets)][u(i)];
        }
        out[k] = product;
      }
    }
  }

  /// t = Σ_j α_j p_j·, one rule at a time: for each rule, kBlock independent multiply-adds of
  /// its (broadcast) α with its contiguous consequents. 1620 multiply-adds for the paper's
  /// 4-output network, the minimum; used when kBlock fills whole 4-lane vectors.
  static void sum_by_rule(const Scalar* consequents, const SetMajor& m, Block& t) noexcept {
    Firing alpha;
    factored_firing(m, alpha);
    // Even and odd rules into separate accumulators: two add chains of half the length.
    Block even{};
    Block odd{};
    const Scalar* rule = consequents;
    int j = 0;
    for (; j + 1 < kRules; j += 2, rule += 2 * kBlock) {
      const Scalar a0 = alpha[u(j)];
      const Scalar a1 = alpha[u(j + 1)];
      for (int k = 0; k < kBlock; ++k) even[u(k)] += a0 * rule[k];
      for (int k = 0; k < kBlock; ++k) odd[u(k)] += a1 * rule[kBlock + k];
    }
    if (j < kRules) {  // kRules odd: the last rule
      const Scalar a0 = alpha[u(j)];
      for (int k = 0; k < kBlock; ++k) even[u(k)] += a0 * rule[k];
    }
    for (int k = 0; k < kBlock; ++k) t[u(k)] = even[u(k)] + odd[u(k)];
  }

  /// α_j = head_p · tail_q for rule j = p·kCols + q (head over the first half of the inputs,
  /// tail over the rest): one multiply per rule after 2·√kRules small products.
  static void factored_firing(const SetMajor& m, Firing& alpha) noexcept {
    std::array<Scalar, kRows> head;
    std::array<Scalar, kCols> tail;
    outer_product<0, kHead>(m, head);
    outer_product<kHead, kInputs>(m, tail);
    for (int p = 0; p < kRows; ++p) {
      for (int q = 0; q < kCols; ++q) alpha[u(p * kCols + q)] = head[u(p)] * tail[u(q)];
    }
  }

  /// sum_by_rule's sums with the loops exchanged: the block is taken 4 values at a time, and
  /// each chunk is summed over every rule (even and odd rules apart, as there). Every
  /// accumulator adds the same products in the same order, so t has the same bits; but only 8
  /// accumulators are live, which a scalar FPU keeps in registers (a Cortex-M7 has 32 single or
  /// 16 double), where sum_by_rule's 2·kBlock would be loaded and stored for every product.
  /// (A member template, so that an explicit instantiation of the class, as training's Jet
  /// test does, compiles it only where `forward` uses it.)
  template <int kChunk = 4>
  static void sum_by_rule_chunked(const Scalar* consequents, const SetMajor& m, Block& t) noexcept {
    static_assert(kChunk == 4, "the loop below is written out for 4 values");
    static_assert(kBlock % kChunk == 0, "the block is a whole number of chunks");
    Firing alpha;
    factored_firing(m, alpha);
    for (int c = 0; c < kBlock; c += kChunk) {
      // Named scalars, not arrays: what makes the compiler keep them in registers.
      Scalar e0{}, e1{}, e2{}, e3{};
      Scalar o0{}, o1{}, o2{}, o3{};
      const Scalar* rule = consequents + c;
      int j = 0;
      for (; j + 1 < kRules; j += 2, rule += 2 * kBlock) {
        const Scalar a0 = alpha[u(j)];
        const Scalar a1 = alpha[u(j + 1)];
        e0 += a0 * rule[0];
        e1 += a0 * rule[1];
        e2 += a0 * rule[2];
        e3 += a0 * rule[3];
        o0 += a1 * rule[kBlock + 0];
        o1 += a1 * rule[kBlock + 1];
        o2 += a1 * rule[kBlock + 2];
        o3 += a1 * rule[kBlock + 3];
      }
      if (j < kRules) {  // kRules odd: the last rule
        const Scalar a0 = alpha[u(j)];
        e0 += a0 * rule[0];
        e1 += a0 * rule[1];
        e2 += a0 * rule[2];
        e3 += a0 * rule[3];
      }
      t[u(c + 0)] = e0 + o0;
      t[u(c + 1)] = e1 + o1;
      t[u(c + 2)] = e2 + o2;
      t[u(c + 3)] = e3 + o3;
    }
  }

  /// t = Σ_j α_j p_j·, without forming α: the consequent block is the tensor
  /// [s_0][s_1]…[s_{n−1}][kBlock] (rule-major, input 0 most significant), contracted with the
  /// memberships of input 0, then input 1, and so on. Each stage is an element-wise weighted sum
  /// of kSets contiguous slices, which vectorises whatever kBlock is: used when a rule's block
  /// does not fill whole vectors (one output: 5 values a rule), where `sum_by_rule` would
  /// shuffle. 2400 multiply-adds for the 4-output network, 600 for one output.
  static void sum_by_contraction(const Scalar* consequents, const SetMajor& m, Block& t) noexcept {
    constexpr int kStage0 = kRules / kSets * kBlock;  // after input 0
    constexpr int kStage1 = kInputs > 1 ? kStage0 / kSets : 1;
    std::array<Scalar, kStage0> a;
    std::array<Scalar, kStage1> b;
    const Scalar* src = consequents;
    int n = kRules * kBlock;
    for (int i = 0; i < kInputs; ++i) {
      const int next = n / kSets;
      Scalar* dst = i == kInputs - 1 ? t.data() : (i % 2 == 0 ? a.data() : b.data());
      for (int e = 0; e < next; ++e) {
        Scalar sum = m[0][u(i)] * src[e];
        for (int s = 1; s < kSets; ++s) sum += m[u(s)][u(i)] * src[s * next + e];
        dst[e] = sum;
      }
      src = dst;
      n = next;
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

/// `model` in another precision, e.g. float for an MCU whose FPU is single precision or twice as
/// fast in it (docs/firmware.md): the ranges stay double (inputs are normalised in double), every
/// parameter is converted by static_cast (round to nearest). constexpr, so that
/// `constexpr auto m32 = convert_model<float>(m64);` places the converted model in read-only
/// memory. Converting a valid double model to float keeps it valid unless a parameter exceeds
/// the float range (find_problem reports it as not finite).
template <typename To, typename From, int kInputs, int kSets, int kOutputs>
constexpr TskModel<To, kInputs, kSets, kOutputs> convert_model(
    const TskModel<From, kInputs, kSets, kOutputs>& model) noexcept {
  TskModel<To, kInputs, kSets, kOutputs> out{};
  out.ranges = model.ranges;
  for (std::size_t k = 0; k < model.params.values.size(); ++k) {
    out.params.values[k] = static_cast<To>(model.params.values[k]);
  }
  return out;
}

/// The paper's network: inputs (PV, PD, AV, AD), 3 sets each, 81 rules, one output (429
/// parameters); one such network per error parameter.
using PaperNetwork = TskModel<double, 4, 3, 1>;
// The paper's premise with one consequent block per error parameter, evaluated in one pass, is
// compensation::Model<PaperInputs> (compensation/move_prediction.hpp): keyed on its inputs.

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
  // Branch-free over the inputs (one SIMD pass where the compiler can): v − v is 0 exactly
  // when v is finite, NaN otherwise.
  const bool clamp = policy == DomainPolicy::kClamp;
  bool finite = true;
  std::uint32_t mask = 0;
  typename Evaluator::Input xn;
  for (int i = 0; i < kInputs; ++i) {
    const auto u = static_cast<unsigned>(i);
    const InputRange& r = model.ranges[u];
    const double v = x[u];
    finite &= (v - v) == 0.0;
    const bool below = v < r.lo;
    const bool above = v > r.hi;
    mask |= static_cast<std::uint32_t>(below | above) << u;
    const double inside = below ? r.lo : (above ? r.hi : v);
    xn[u] = static_cast<Scalar>(normalise(clamp ? inside : v, r));
  }
  if (!finite) return Status::kInvalidInput;
  if (outside_mask != nullptr) *outside_mask = mask;
  if (mask != 0 && policy == DomainPolicy::kReject) return Status::kOutsideDomainRejected;

  typename Evaluator::Output out;
  Evaluator::forward(model.params.data(), xn, out);
  for (int o = 0; o < kOutputs; ++o) {
    const Scalar v = out[static_cast<unsigned>(o)];
    finite &= (v - v) == Scalar(0);
  }
  if (!finite) return Status::kInvalidInput;
  for (int o = 0; o < kOutputs; ++o) {
    y[static_cast<unsigned>(o)] = static_cast<double>(out[static_cast<unsigned>(o)]);
  }
  return mask != 0 ? Status::kOutsideDomain : Status::kOk;
}

/// What `find_problem` found wrong with a model (kNone: it may be published).
struct ModelProblem {
  enum Kind : std::uint8_t {
    kNone,              ///< no problem
    kRangeNotFinite,    ///< range `input`: lo, hi or hi − lo is not finite
    kRangeEmpty,        ///< range `input`: lo >= hi
    kParamNotFinite,    ///< parameter `index` is NaN or ±inf
    kWidthNotPositive,  ///< width of set `set` of input `input` is not > 0
  };
  Kind kind = kNone;
  int input = -1;  ///< the input concerned (range and width problems)
  int set = -1;    ///< the set concerned (width problems)
  int index = -1;  ///< the parameter concerned (kParamNotFinite)

  constexpr explicit operator bool() const noexcept { return kind != kNone; }
};

/// The first reason `model` may not be published: a range not finite or with lo >= hi, a
/// parameter not finite, a width not > 0; kind kNone when there is none. RT-safe (no
/// allocation, bounded), so that firmware without a heap can check a model before publishing.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
constexpr ModelProblem find_problem(
    const TskModel<Scalar, kInputs, kSets, kOutputs>& model) noexcept {
  static_assert(std::is_floating_point_v<Scalar>, "find_problem checks double or float models");
  using Layout = TskLayout<kInputs, kSets, kOutputs>;
  // v − v is 0 exactly when v is finite (constexpr, unlike std::isfinite in C++17).
  const auto finite = [](auto v) { return (v - v) == decltype(v)(0); };
  for (int i = 0; i < kInputs; ++i) {
    const InputRange& r = model.ranges[static_cast<unsigned>(i)];
    if (!finite(r.lo) || !finite(r.hi) || !finite(r.hi - r.lo)) {
      return {ModelProblem::kRangeNotFinite, i, -1, -1};
    }
    if (!(r.lo < r.hi)) return {ModelProblem::kRangeEmpty, i, -1, -1};
  }
  for (int k = 0; k < Layout::kParamCount; ++k) {
    if (!finite(model.params.values[static_cast<unsigned>(k)])) {
      return {ModelProblem::kParamNotFinite, -1, -1, k};
    }
  }
  for (int i = 0; i < kInputs; ++i) {
    for (int s = 0; s < kSets; ++s) {
      if (!(model.params.width(i, s) > Scalar(0)))
        return {ModelProblem::kWidthNotPositive, i, s, -1};
    }
  }
  return {};
}

/// Checks that `model` may be published (find_problem). Setup only (may allocate for `why`). On
/// failure returns false and, if `why` is given, stores the first problem found.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
bool validate(const TskModel<Scalar, kInputs, kSets, kOutputs>& model, std::string* why = nullptr) {
  const ModelProblem p = find_problem(model);
  if (!p) return true;
  if (why != nullptr) {
    switch (p.kind) {
      case ModelProblem::kRangeNotFinite:
        *why = "range of input " + std::to_string(p.input) + " is not finite";
        break;
      case ModelProblem::kRangeEmpty:
        *why = "range of input " + std::to_string(p.input) + " has lo >= hi";
        break;
      case ModelProblem::kParamNotFinite:
        *why = "parameter " + std::to_string(p.index) + " is not finite";
        break;
      case ModelProblem::kWidthNotPositive:
        *why = "width of set " + std::to_string(p.set) + " of input " + std::to_string(p.input) +
               " is not positive";
        break;
      case ModelProblem::kNone:
        break;
    }
  }
  return false;
}

}  // namespace cmmcomp::fuzzy
