// SPDX-License-Identifier: MIT
/// @file Loads a model file of any served input set for the compensator (names and units
/// checked against the schema) and publishes it to an axis.
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstdlib>
#include <utility>

namespace cmmcomp::io {

namespace {

/// "4 x 3 x 4 (PV, PD, AV, AD) or 5 x 3 x 4 (PV, PD, AV, AD, Y)".
template <typename... Sets>
std::string served_architectures(InputSetList<Sets...> /*unused*/) {
  std::string s;
  const auto one = [&s](auto set) {
    using Inputs = decltype(set);
    if (!s.empty()) s += " or ";
    s += std::to_string(Inputs::kCount) + " x " + std::to_string(compensation::kSetsPerInput) +
         " x " + std::to_string(compensation::kModelOutputs) + " (";
    const auto labels = Inputs::labels();
    for (std::size_t i = 0; i < labels.size(); ++i)
      s += (i == 0 ? "" : ", ") + std::string(labels[i]);
    s += ")";
  };
  (one(Sets{}), ...);
  return s;
}

/// The first served set (in ServedInputSets order) of `a`'s size whose names the file has;
/// the problem with the first set of that size if none has them.
template <typename Set, typename... Rest>
bool parse_as(const std::string& text,
              const std::string& source,
              const ModelArchitecture& a,
              CompensationModelFile& out,
              std::string& first_problem) {
  if (a.inputs == Set::kCount && a.sets_per_input == compensation::kSetsPerInput &&
      a.outputs == compensation::kModelOutputs) {
    auto file =
        parse_model_json<Set::kCount, compensation::kSetsPerInput, compensation::kModelOutputs>(
            text, source);
    std::string problem = schema_name_problem<Set>(file);
    if (problem.empty()) {
      out.template emplace<ModelFileOf<Set>>(std::move(file));
      return true;
    }
    if (first_problem.empty()) first_problem = std::move(problem);
  }
  if constexpr (sizeof...(Rest) > 0) {
    return parse_as<Rest...>(text, source, a, out, first_problem);
  } else {
    return false;
  }
}

template <typename... Sets>
bool parse_served(const std::string& text,
                  const std::string& source,
                  const ModelArchitecture& a,
                  CompensationModelFile& out,
                  std::string& first_problem,
                  InputSetList<Sets...> /*unused*/) {
  return parse_as<Sets...>(text, source, a, out, first_problem);
}

}  // namespace

CompensationModelFile parse_compensation_model(const std::string& text, const std::string& source) {
  const ModelArchitecture a = read_model_architecture(text, source);
  CompensationModelFile file;
  std::string problem;
  if (parse_served(text, source, a, file, problem, ServedInputSets{})) return file;
  if (!problem.empty()) throw ConfigError(source + ": " + problem);
  throw ConfigError(source + ": architecture " + std::to_string(a.inputs) + " inputs x " +
                    std::to_string(a.sets_per_input) + " sets x " + std::to_string(a.outputs) +
                    " outputs; the compensator serves " + served_architectures(ServedInputSets{}));
}

CompensationModelFile load_compensation_model(const std::string& path) {
  return parse_compensation_model(detail::read_text_file(path, "model file"), path);
}

compensation::Conditions compensation_conditions(const TrainingConditions& conditions) {
  compensation::Conditions c;
  if (conditions.pa_mm_s2) c.pa_mm_s2 = {conditions.pa_mm_s2->lo, conditions.pa_mm_s2->hi};
  if (conditions.aa_mm_s2) c.aa_mm_s2 = {conditions.aa_mm_s2->lo, conditions.aa_mm_s2->hi};
  return c;
}

const TrainingConditions& training_conditions(const CompensationModelFile& file) {
  return std::visit([](const auto& f) -> const TrainingConditions& { return f.conditions; }, file);
}

const std::string& model_id(const CompensationModelFile& file) {
  return std::visit([](const auto& f) -> const std::string& { return f.model_id; }, file);
}

std::uint64_t numeric_model_id(const CompensationModelFile& file) {
  return std::strtoull(model_id(file).c_str(), nullptr, 16);
}

int model_inputs(const CompensationModelFile& file) {
  return std::visit([](const auto& f) { return std::decay_t<decltype(f)>::InputSet::kCount; },
                    file);
}

Status publish(compensation::MoveCompensator& compensator,
               int axis,
               const CompensationModelFile& file,
               std::string* why) {
  const double coverage = std::visit([](const auto& f) { return f.interval.coverage; }, file);
  if (coverage != 0.0 && coverage != kServedCoverage) {
    if (why != nullptr) {
      *why = fmt::format(
          "the model's interval is calibrated at {:g} % coverage, but every interface of the "
          "compensator reports U95, the half-width at {:g} % (Correction::u95_um, the C ABI, "
          "Modbus, CAN): retrain it with cmmcomp-train fit --interval-coverage {:g}",
          100.0 * coverage,
          100.0 * kServedCoverage,
          kServedCoverage);
    }
    return Status::kInvalidInput;
  }
  return publish_at_its_coverage(compensator, axis, file, why);
}

Status publish_at_its_coverage(compensation::MoveCompensator& compensator,
                               int axis,
                               const CompensationModelFile& file,
                               std::string* why) {
  const std::uint64_t id = numeric_model_id(file);
  return std::visit(
      [&](const auto& f) {
        return compensator.publish(axis,
                                   f.compensation_model(),
                                   f.interval,
                                   compensation_conditions(f.conditions),
                                   id,
                                   why);
      },
      file);
}

}  // namespace cmmcomp::io
