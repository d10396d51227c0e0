/* SPDX-License-Identifier: MIT */
/** @file C ABI of the firmware compensator: no heap, no file system, no OS (C99).
 *
 * For controller firmware in C on an MCU (docs/firmware.md). The model is compiled into the
 * image: `cmmcomp-train export MODEL.json --c-source model.c --symbol NAME [--scalar float]`
 * writes a `const cmmcomp_fw_model NAME` (and NAME_id) in the layout below. One static
 * compensator serves every axis; its storage is in the library's .bss (2 buffers per axis).
 *
 * The model's shape is fixed when the firmware is built, by two macros that the library and
 * every file including this header must agree on (the build passes them to both):
 *   CMMCOMP_FW_INPUTS   4 (PV, PD, AV, AD; default) or 5 (and Y)
 *   CMMCOMP_FW_SCALAR   float (default: a Cortex-M7 evaluates it in 8290 instructions) or double
 * Threading: one publisher (main loop) and readers that preempt it (interrupts, higher-priority
 * tasks on the same core), as compensation/static_compensator.hpp explains. Request, correction,
 * flags and codes are those of compensator.h. The request's `direction` is d, the direction of
 * motion, the opposite of the probed surface's normal: d = -IJK (a point on a face with normal
 * IJK = (1, 0, 0) is approached moving in -X, so d = (-1, 0, 0)); sending the normal instead
 * flips the sign of every correction without an error (docs/measurement.md, "plan.csv"). */
#ifndef CMMCOMP_COMPENSATOR_FW_H
#define CMMCOMP_COMPENSATOR_FW_H

#include <cmmcomp/compensator.h>
#include <stdint.h>

#ifndef CMMCOMP_FW_INPUTS
#define CMMCOMP_FW_INPUTS 4
#endif
#ifndef CMMCOMP_FW_SCALAR
#define CMMCOMP_FW_SCALAR float
#endif
#if CMMCOMP_FW_INPUTS != 4 && CMMCOMP_FW_INPUTS != 5
#error "CMMCOMP_FW_INPUTS must be 4 or 5"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** Rules of the network: 3 Gaussian sets per input, 3^inputs. */
#define CMMCOMP_FW_RULES (CMMCOMP_FW_INPUTS == 5 ? 243 : 81)
/** Parameters (docs/model-file.md, tsk_params.hpp): centres and widths, 3 per input, then
 * 4 outputs x rules x (inputs + 1) consequents. */
#define CMMCOMP_FW_PARAMS \
  (2 * 3 * CMMCOMP_FW_INPUTS + 4 * CMMCOMP_FW_RULES * (CMMCOMP_FW_INPUTS + 1))

/** A model in memory, in the evaluator's layout: what the exported C source defines. */
typedef struct cmmcomp_fw_model {
  double ranges[CMMCOMP_FW_INPUTS][2];         /**< {lo, hi} of each input, raw units */
  CMMCOMP_FW_SCALAR params[CMMCOMP_FW_PARAMS]; /**< normalised-input parameters */
} cmmcomp_fw_model;

/** The calibration of a model's 95 % prediction interval (docs/uncertainty.md): for output o
 * (MPE, RPE, MAE, RAE), U95 = half_width[o] * (1 + corner_gain[o] * kappa + extrapolation_gain[o]
 * * d), kappa and d from the move's inputs. What the exported C source defines as
 * NAME_interval. coverage 0 (every value 0): none, and the correction's interval is "unknown". */
typedef struct cmmcomp_fw_interval_calibration {
  double coverage;              /**< nominal coverage in (0, 1), or 0: none */
  double half_width[4];         /**< in-domain half-width [um], finite, >= 0 */
  double extrapolation_gain[4]; /**< growth per training range outside the box, >= 0 */
  double corner_gain[4];        /**< growth at the box's corners, >= 0 */
} cmmcomp_fw_interval_calibration;

/** The accelerations a model was trained at (its file's `conditions`; docs/compensator.md,
 * "Domain"): a move whose PA or AA lies outside is flagged CMMCOMP_FLAG_OUTSIDE_DOMAIN, or
 * refused (CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED) under policy reject; one far outside (beyond by more
 * than 10 % of the range, or of the value for a single trained value) is refused under every
 * policy, as is a move whose network input lies that far outside its training range. What the
 * exported C source defines as NAME_conditions. {0, 0}: unknown, not checked. */
typedef struct cmmcomp_fw_conditions {
  double pa_mm_s2[2]; /**< {lo, hi} of the trained PA [mm/s^2], 0 < lo <= hi, or {0, 0} */
  double aa_mm_s2[2]; /**< {lo, hi} of the trained AA [mm/s^2], 0 < lo <= hi, or {0, 0} */
} cmmcomp_fw_conditions;

/** Outside-domain policy of every before_approach (fixed before the first publish):
 * 0 clamp (default), 1 extrapolate, 2 reject. Not RT-safe; returns CMMCOMP_E_ARGUMENT for any
 * other value or once a model has been published. */
int cmmcomp_fw_set_outside_domain(int policy);

/** Copies `model` into the free buffer of `axis` and makes it serve every before_approach that
 * starts after this returns. Publisher only; bounded time (one copy of the model), no
 * allocation, never waits. Returns 0; CMMCOMP_E_ARGUMENT (null model, axis >=
 * CMMCOMP_MAX_AXES); CMMCOMP_E_MODEL (a range not finite or empty, a parameter not finite, a
 * width <= 0); CMMCOMP_E_BUSY (a reader is inside that buffer: the contract is broken). On
 * error the old model keeps serving. */
int cmmcomp_fw_publish(uint32_t axis, const cmmcomp_fw_model* model, uint64_t model_id);

/** As cmmcomp_fw_publish, with the model's interval calibration (NAME_interval of the exported
 * source), copied into the same buffer so that a hot swap changes both at once. Also
 * CMMCOMP_E_ARGUMENT for a null `interval`, CMMCOMP_E_MODEL for a calibration that is not valid
 * (a value negative or not finite, a coverage outside [0, 1), values without a coverage).
 * cmmcomp_fw_publish publishes no calibration. */
int cmmcomp_fw_publish_with_interval(uint32_t axis,
                                     const cmmcomp_fw_model* model,
                                     const cmmcomp_fw_interval_calibration* interval,
                                     uint64_t model_id);

/** As cmmcomp_fw_publish_with_interval, with the model's training conditions (NAME_conditions
 * of the exported source) published into the same buffer: what every model trained by
 * cmmcomp-train should be published with. `interval` may be NULL (no calibration); also
 * CMMCOMP_E_ARGUMENT for a null `conditions`, CMMCOMP_E_MODEL for conditions that are not
 * {0, 0} or finite with 0 < lo <= hi. */
int cmmcomp_fw_publish_with_conditions(uint32_t axis,
                                       const cmmcomp_fw_model* model,
                                       const cmmcomp_fw_interval_calibration* interval,
                                       const cmmcomp_fw_conditions* conditions,
                                       uint64_t model_id);

/** As cmmcomp_before_approach (compensator.h), on the firmware compensator. RT-safe, callable
 * from an interrupt handler: no allocation, no lock, no syscall. */
int cmmcomp_fw_before_approach(const cmmcomp_move_request* in, cmmcomp_correction* out);

/** As cmmcomp_fw_before_approach, and writes the correction's 95 % interval into `interval`
 * (u95_um and every flag; CMMCOMP_FLAG_NO_UNCERTAINTY when the model was published without a
 * calibration), as cmmcomp_before_approach_with_interval does. RT-safe. CMMCOMP_E_ARGUMENT for
 * a null pointer; `out` and `interval` are untouched on any error. */
int cmmcomp_fw_before_approach_with_interval(const cmmcomp_move_request* in,
                                             cmmcomp_correction* out,
                                             cmmcomp_interval* interval);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* CMMCOMP_COMPENSATOR_FW_H */
