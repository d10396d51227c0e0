// SPDX-License-Identifier: MIT
/// @file The components of the core as firmware links them, compiled for the Cortex-M7 once per
/// component (CMMCOMP_FW_COMPONENT_*, tests/firmware/CMakeLists.txt) so that
/// scripts/firmware-figures.sh can report each one's .text, .rodata and .bss and its worst-case
/// stack (-fstack-usage, -fcallgraph-info=su). The figures image calls them, so their code is
/// what the instruction counts measure.
#include "components.hpp"

#include <cmmcomp/compensation/static_compensator.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/motion/move_profile.hpp>

#include "default.hpp"

namespace {
using ModelF = cmmcomp::compensation::Model<cmmcomp::PaperInputs, float>;
[[maybe_unused]] constexpr ModelF kDefaultF{cmmcomp::fuzzy::convert_model<float>(default_model)};
}  // namespace

extern "C" {

#if defined(CMMCOMP_FW_COMPONENT_EVALUATE_DOUBLE)

int cmmcomp_fw_evaluate_double(const double x[4], double y[4]) {
  std::array<double, 4> out{};
  const auto s = cmmcomp::fuzzy::evaluate(
      default_model, {x[0], x[1], x[2], x[3]}, out, cmmcomp::fuzzy::DomainPolicy::kClamp);
  for (int o = 0; o < 4; ++o) y[o] = out[static_cast<unsigned>(o)];
  return static_cast<int>(s);
}

#elif defined(CMMCOMP_FW_COMPONENT_EVALUATE_FLOAT)
int cmmcomp_fw_evaluate_float(const double x[4], double y[4]) {
  std::array<double, 4> out{};
  const auto s = cmmcomp::fuzzy::evaluate(
      kDefaultF, {x[0], x[1], x[2], x[3]}, out, cmmcomp::fuzzy::DomainPolicy::kClamp);
  for (int o = 0; o < 4; ++o) y[o] = out[static_cast<unsigned>(o)];
  return static_cast<int>(s);
}

#elif defined(CMMCOMP_FW_COMPONENT_COMPENSATOR_DOUBLE)
namespace {
cmmcomp::compensation::StaticMoveCompensator<cmmcomp::compensation::Model<cmmcomp::PaperInputs> >
    g_comp_d;
}
int cmmcomp_fw_publish_double(int axis) {
  return static_cast<int>(g_comp_d.publish(axis, default_model, 1));
}
int cmmcomp_fw_before_approach_double(const cmmcomp::compensation::MoveRequest* move,
                                      cmmcomp::compensation::Correction* out) {
  return static_cast<int>(g_comp_d.before_approach(*move, *out));
}

#elif defined(CMMCOMP_FW_COMPONENT_COMPENSATOR_FLOAT)
namespace {
cmmcomp::compensation::StaticMoveCompensator<ModelF> g_comp_f;
}
int cmmcomp_fw_publish_float(int axis) {
  return static_cast<int>(g_comp_f.publish(axis, kDefaultF, 2));
}

int cmmcomp_fw_before_approach_float(const cmmcomp::compensation::MoveRequest* move,
                                     cmmcomp::compensation::Correction* out) {
  return static_cast<int>(g_comp_f.before_approach(*move, *out));
}

#elif defined(CMMCOMP_FW_COMPONENT_PROFILE_EXTRACT)
int cmmcomp_fw_profile_and_extract(const double* time,
                                   const double* error,
                                   std::size_t count,
                                   double errors_um[4]) {
  cmmcomp::motion::MoveProfile profile;
  const auto planned =
      cmmcomp::motion::MoveProfile::plan(cmmcomp::motion::baseline_move(), profile);
  if (!cmmcomp::ok(planned)) return static_cast<int>(planned);
  cmmcomp::errors::DynamicErrors e;
  const auto s = cmmcomp::errors::extract_dynamic_errors(
      cmmcomp::errors::TraceView{time, error, count}, profile.instants(), 1, e);
  if (!cmmcomp::ok(s)) return static_cast<int>(s);
  errors_um[0] = e.mpe;
  errors_um[1] = e.rpe;
  errors_um[2] = e.mae;
  errors_um[3] = e.rae;
  return 0;
}

double cmmcomp_fw_profile_duration() {
  cmmcomp::motion::MoveProfile profile;
  return cmmcomp::ok(cmmcomp::motion::MoveProfile::plan(cmmcomp::motion::baseline_move(), profile))
             ? profile.duration()
             : -1.0;
}

#else
#error "define one CMMCOMP_FW_COMPONENT_*"
#endif

}  // extern "C"
