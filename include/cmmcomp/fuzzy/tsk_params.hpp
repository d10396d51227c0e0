// SPDX-License-Identifier: MIT
/// @file Sizes and flat parameter layout of the fixed-size Takagi–Sugeno fuzzy neural network.
///
/// One flat block of `kParamCount` values holds every trained parameter, so that Ceres can
/// consume it as one parameter block and a model file can store it as one array:
///
///     offset                                  contents                       shape
///     0                                       centres c                      [kSets][kInputs]
///     kInputs·kSets                           widths σ                       [kSets][kInputs]
///     2·kInputs·kSets                         consequents p [kRules][kOutputs][kInputs+1]
///     kParamCount = 2·kInputs·kSets + kOutputs·kRules·(kInputs+1)
///
/// All arrays are row-major (last index fastest). Consequent term 0 of a rule is its constant
/// p_j0; term 1 + i multiplies normalised input i (y_j = p_j0 + Σ_i p_j,1+i x_i). Centres and
/// widths live in normalised input units (the training range maps onto [0, 1]).
///
/// Why this order: it is the order the real-time evaluator reads (tsk_evaluator.hpp). Set-major
/// centres and widths put one set of every input in contiguous memory, so the memberships of
/// all inputs are computed as a few whole SIMD vectors; rule-major consequents put everything
/// one rule contributes to every output in kOutputs·(kInputs+1) contiguous values, so the
/// consequent sums are one pass of independent multiply-adds over the block. Code outside the
/// evaluator addresses the block through `centre_index`, `width_index` and `consequent_index`
/// (or the TskParams accessors) and never assumes the order; the model file stores nested
/// arrays, not this block (docs/model-file.md), so the order is not part of any file format.
///
/// Rule numbering: rule j fires on one set per input; the set of input i is digit i of j
/// written in base kSets with **input 0 the most significant digit**:
///     j = ((s_0·kSets + s_1)·kSets + s_2)·kSets + … + s_{kInputs−1}.
/// For the paper's 4 × 3 network, rule 0 is (0,0,0,0), rule 1 is (0,0,0,1), rule 3 is
/// (0,0,1,0) and rule 80 is (2,2,2,2).
#pragma once

#include <array>

namespace cmmcomp::fuzzy {

namespace detail {

/// base^exponent for small non-negative integers, at compile time; -1 above 2^20.
constexpr int checked_pow(int base, int exponent) noexcept {
  long long r = 1;
  for (int i = 0; i < exponent; ++i) {
    r *= base;
    if (r > (1LL << 20)) return -1;
  }
  return static_cast<int>(r);
}

}  // namespace detail

/// The flat layout's index arithmetic for sizes known only at run time (the model file's
/// reader and writer). TskLayout's compile-time functions are this same formula.
struct RuntimeLayout {
  int inputs;   ///< inputs of the network
  int sets;     ///< Gaussian sets per input
  int outputs;  ///< outputs (consequent blocks)

  /// sets^inputs; -1 above 2^20.
  constexpr int rules() const noexcept { return detail::checked_pow(sets, inputs); }
  /// Consequent terms per rule and output: the constant and one coefficient per input.
  constexpr int terms() const noexcept { return inputs + 1; }
  constexpr int widths_offset() const noexcept { return inputs * sets; }
  constexpr int consequents_offset() const noexcept { return 2 * inputs * sets; }
  /// 2·inputs·sets + outputs·rules·(inputs + 1).
  constexpr int param_count() const noexcept {
    return consequents_offset() + outputs * rules() * terms();
  }
  constexpr int centre_index(int input, int set) const noexcept { return set * inputs + input; }
  constexpr int width_index(int input, int set) const noexcept {
    return widths_offset() + set * inputs + input;
  }
  constexpr int consequent_index(int output, int rule, int term) const noexcept {
    return consequents_offset() + (rule * outputs + output) * terms() + term;
  }
};

/// Sizes and index arithmetic of a network with `kInputs` inputs, `kSets` Gaussian sets per
/// input and `kOutputs` outputs sharing one premise (kOutputs = 1 is the paper's form).
template <int kInputs, int kSets, int kOutputs>
struct TskLayout {
  static_assert(kInputs > 0 && kSets > 0 && kOutputs > 0, "sizes must be positive");
  static_assert(kInputs <= 32, "the outside-domain mask has 32 bits");
  static_assert(detail::checked_pow(kSets, kInputs) > 0, "more than 2^20 rules");

  static constexpr int kInputCount = kInputs;    ///< inputs of the network
  static constexpr int kSetCount = kSets;        ///< Gaussian sets per input
  static constexpr int kOutputCount = kOutputs;  ///< outputs (consequent blocks)
  /// The same sizes at run time: every index below is its formula.
  static constexpr RuntimeLayout kRuntime{kInputs, kSets, kOutputs};
  /// Rules: one per combination of sets, kSets^kInputs.
  static constexpr int kRules = kRuntime.rules();
  /// Consequent terms per rule and output: the constant and one coefficient per input.
  static constexpr int kTerms = kRuntime.terms();
  static constexpr int kCentresOffset = 0;                                  ///< first centre
  static constexpr int kWidthsOffset = kRuntime.widths_offset();            ///< first width
  static constexpr int kConsequentsOffset = kRuntime.consequents_offset();  ///< first consequent
  /// Consequent values of one output, kRules·kTerms.
  static constexpr int kConsequentBlock = kRules * kTerms;
  /// Consequent values of one rule, all outputs: kOutputs·kTerms (contiguous).
  static constexpr int kRuleBlock = kOutputs * kTerms;
  /// Total number of parameters: 2·kInputs·kSets + kOutputs·kRules·(kInputs + 1).
  static constexpr int kParamCount = kRuntime.param_count();
  static_assert(kParamCount == kConsequentsOffset + kOutputs * kConsequentBlock);

  /// Flat index of the centre of set `set` of input `input`.
  static constexpr int centre_index(int input, int set) noexcept {
    return kRuntime.centre_index(input, set);
  }
  /// Flat index of the width σ of set `set` of input `input`.
  static constexpr int width_index(int input, int set) noexcept {
    return kRuntime.width_index(input, set);
  }
  /// Flat index of consequent term `term` (0 = constant, 1 + i = coefficient of input i) of
  /// rule `rule` for output `output`.
  static constexpr int consequent_index(int output, int rule, int term) noexcept {
    return kRuntime.consequent_index(output, rule, term);
  }
  /// The set rule `rule` uses for input `input`: digit `input` of `rule` in base kSets, input 0
  /// being the most significant digit.
  static constexpr int rule_set(int rule, int input) noexcept {
    for (int i = kInputs - 1; i > input; --i) rule /= kSets;
    return rule % kSets;
  }
  /// The rule firing on `sets[i]` for each input i (inverse of rule_set).
  static constexpr int rule_index(const std::array<int, kInputs>& sets) noexcept {
    int j = 0;
    for (int i = 0; i < kInputs; ++i) j = j * kSets + sets[static_cast<unsigned>(i)];
    return j;
  }
};

/// The trained parameters of one network, in the flat layout above. Plain value type (no heap);
/// `Scalar` is double or float on the RT path, a ceres::Jet in training.
template <typename Scalar, int kInputs, int kSets, int kOutputs>
struct TskParams : TskLayout<kInputs, kSets, kOutputs> {
  using Layout = TskLayout<kInputs, kSets, kOutputs>;
  using Layout::kParamCount;

  std::array<Scalar, kParamCount> values{};  ///< flat block, layout in the file comment

  constexpr Scalar* data() noexcept { return values.data(); }
  constexpr const Scalar* data() const noexcept { return values.data(); }

  /// Centre of set `set` of input `input` [normalised input units].
  constexpr Scalar& centre(int input, int set) noexcept {
    return at(Layout::centre_index(input, set));
  }
  constexpr const Scalar& centre(int input, int set) const noexcept {
    return at(Layout::centre_index(input, set));
  }
  /// Width σ of set `set` of input `input` [normalised input units], > 0.
  constexpr Scalar& width(int input, int set) noexcept {
    return at(Layout::width_index(input, set));
  }
  constexpr const Scalar& width(int input, int set) const noexcept {
    return at(Layout::width_index(input, set));
  }
  /// Consequent term `term` of rule `rule` for output `output` (0 = constant, 1 + i = input i).
  constexpr Scalar& consequent(int output, int rule, int term) noexcept {
    return at(Layout::consequent_index(output, rule, term));
  }
  constexpr const Scalar& consequent(int output, int rule, int term) const noexcept {
    return at(Layout::consequent_index(output, rule, term));
  }

 private:
  constexpr Scalar& at(int i) noexcept { return values[static_cast<unsigned>(i)]; }
  constexpr const Scalar& at(int i) const noexcept { return values[static_cast<unsigned>(i)]; }
};

}  // namespace cmmcomp::fuzzy
