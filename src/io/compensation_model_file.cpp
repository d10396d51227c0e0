// SPDX-License-Identifier: MIT
/// @file Loads a 4- or 5-input model file for the compensator (names and units checked) and
/// publishes it to an axis.
#include <cmmcomp/error.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstdlib>
#include <utility>

namespace cmmcomp::io {

namespace {

template <typename File>
void require_paper_names(const File& file, const std::string& source) {
  File expected;
  set_paper_names(expected);
  const auto check = [&source](const auto& got, const auto& want, const char* what) {
    for (std::size_t k = 0; k < want.size(); ++k) {
      if (got[k] != want[k]) {
        throw ConfigError(source + ": " + what + " " + std::to_string(k) + " is '" + got[k] +
                          "'; the compensator feeds '" + want[k] + "' there");
      }
    }
  };
  check(file.input_names, expected.input_names, "input");
  check(file.input_units, expected.input_units, "unit of input");
  check(file.output_names, expected.output_names, "output");
  check(file.output_units, expected.output_units, "unit of output");
}

template <typename File>
CompensationModelFile checked(File file, const std::string& source) {
  require_paper_names(file, source);
  return CompensationModelFile{std::move(file)};
}

}  // namespace

CompensationModelFile parse_compensation_model(const std::string& text, const std::string& source) {
  const ModelArchitecture a = read_model_architecture(text, source);
  if (a.sets_per_input == 3 && a.outputs == 4 && a.inputs == 5) {
    return checked(parse_model_json<5, 3, 4>(text, source), source);
  }
  if (a.sets_per_input == 3 && a.outputs == 4 && a.inputs == 4) {
    return checked(parse_model_json<4, 3, 4>(text, source), source);
  }
  throw ConfigError(source + ": architecture " + std::to_string(a.inputs) + " inputs x " +
                    std::to_string(a.sets_per_input) + " sets x " + std::to_string(a.outputs) +
                    " outputs; the compensator serves 4 x 3 x 4 (PV, PD, AV, AD) or 5 x 3 x 4 "
                    "(PV, PD, AV, AD, Y)");
}

CompensationModelFile load_compensation_model(const std::string& path) {
  return parse_compensation_model(detail::read_text_file(path, "model file"), path);
}

const std::string& model_id(const CompensationModelFile& file) {
  return std::visit([](const auto& f) -> const std::string& { return f.model_id; }, file);
}

std::uint64_t numeric_model_id(const CompensationModelFile& file) {
  return std::strtoull(model_id(file).c_str(), nullptr, 16);
}

int model_inputs(const CompensationModelFile& file) {
  return std::holds_alternative<PaperModelFileY>(file) ? 5 : 4;
}

Status publish(compensation::MoveCompensator& compensator,
               int axis,
               const CompensationModelFile& file,
               std::string* why) {
  const std::uint64_t id = numeric_model_id(file);
  return std::visit([&](const auto& f) { return compensator.publish(axis, f.model, id, why); },
                    file);
}

}  // namespace cmmcomp::io
