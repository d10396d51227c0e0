/* SPDX-License-Identifier: MIT */
/** @file C ABI of the per-move compensator (C99), for controller software in C: a vendor's
 * controller plugin, a PLC runtime, firmware with a file system. cmmcomp's own bus servers
 * (plugins/, static C++ libraries in cmmcomp-agent) use the C++ API directly.
 *
 * One compensator holds one model file that serves every axis: a 3-set, 4-output T-S network
 * with the paper's 4 inputs (PV, PD, AV, AD) or 5 with Y (y_mm), as cmmcomp-train writes it
 * (io/compensation_model_file.hpp). Units are in the field names; signs and the threading
 * rules are in docs/compensator.md. Every function returns 0 or a negative
 * CMMCOMP_E* code (except the accessors noted); no exception crosses this boundary. */
#ifndef CMMCOMP_COMPENSATOR_H
#define CMMCOMP_COMPENSATOR_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#if defined(CMMCOMP_CAPI_BUILDING)
#define CMMCOMP_CAPI_EXPORT __declspec(dllexport)
#else
#define CMMCOMP_CAPI_EXPORT __declspec(dllimport)
#endif
#elif defined(__GNUC__)
#define CMMCOMP_CAPI_EXPORT __attribute__((visibility("default")))
#else
#define CMMCOMP_CAPI_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** Version of this ABI: bumped on any incompatible change of a struct or a signature. */
#define CMMCOMP_ABI_VERSION 1u

/** Axes served (cmmcomp_move_request.axis < CMMCOMP_MAX_AXES). */
#define CMMCOMP_MAX_AXES 4u
/** Largest model file accepted, in bytes (the shipped 4x3x4 and 5x3x4 default models are
 * about 39 kB and 129 kB). */
#define CMMCOMP_MAX_MODEL_BYTES 4194304u /* 4 MiB */
/** Longest string cmmcomp_strerror and cmmcomp_version return, without the terminating 0. */
#define CMMCOMP_MAX_MESSAGE_LENGTH 80u

/** Correction flags (cmmcomp_correction.flags). */
#define CMMCOMP_FLAG_OK 0x1u             /**< the correction is valid and may be applied */
#define CMMCOMP_FLAG_OUTSIDE_DOMAIN 0x2u /**< input outside the training ranges; clamped */
#define CMMCOMP_FLAG_INVALID_INPUT 0x4u  /**< request rejected (never set in a written output) */
#define CMMCOMP_FLAG_NO_MODEL 0x8u       /**< no model (never set in a written output) */
/** The model carries no interval calibration: cmmcomp_interval.u95_um is 0 and means
 * "unknown". Set only in cmmcomp_interval.flags (cmmcomp_correction keeps the bits above). */
#define CMMCOMP_FLAG_NO_UNCERTAINTY 0x10u

/** Return codes: 0 = ok, negative = error. The RT codes equal cmmcomp::Status values. */
#define CMMCOMP_OK 0
#define CMMCOMP_E_ARGUMENT (-1)        /**< a null pointer or a size out of range */
#define CMMCOMP_E_IO (-2)              /**< the model file cannot be opened or read */
#define CMMCOMP_E_MODEL (-3)           /**< not a valid 4x3x4 or 5x3x4 model file (see above) */
#define CMMCOMP_E_NO_MEMORY (-4)       /**< allocation failed */
#define CMMCOMP_E_INTERNAL (-5)        /**< an unexpected internal error */
#define CMMCOMP_E_INVALID_INPUT (-100) /**< NaN, inf, <= 0, bad axis or direction in a request */
#define CMMCOMP_E_NO_MODEL (-101)      /**< no model published (not returned by this ABI today) */
/** outside the training domain and rejected: under the policy reject, or far outside (an input
 * or the PA or AA beyond the model's range by more than 10 % of it) under any policy
 * (docs/compensator.md, "Domain"); the C ABI's policy is clamp, so here only far outside */
#define CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED (-103)
#define CMMCOMP_E_BUSY (-104) /**< firmware publish: a reader holds the buffer */

/** One probing move, announced before its approach. `direction` is d, the direction of motion,
 * the opposite of the probed surface's normal: d = -IJK (a point on a face with normal
 * IJK = (1, 0, 0) is approached moving in -X, so d = (-1, 0, 0)); sending the normal instead
 * flips the sign of every correction without an error (docs/measurement.md, "plan.csv"). */
typedef struct cmmcomp_move_request {
  uint32_t sequence;   /**< echoed in the correction */
  uint32_t axis;       /**< moving axis, < CMMCOMP_MAX_AXES */
  double direction[3]; /**< approach direction d, unit vector (|d| = 1 +- 1e-6), machine frame */
  double pv_mm_s;      /**< positioning speed PV [mm/s], > 0 */
  double pa_mm_s2;     /**< positioning acceleration PA [mm/s^2], > 0 */
  double pd_mm;        /**< positioning distance PD [mm], > 0 */
  double av_mm_s;      /**< approach speed AV [mm/s], > 0 */
  double aa_mm_s2;     /**< approach acceleration AA [mm/s^2], > 0 */
  double ad_mm;        /**< approach distance AD [mm], > 0 */
  double y_mm;         /**< carriage position [mm], finite */
  double z_mm;         /**< ram position [mm], finite */
} cmmcomp_move_request;

/** The predicted errors and the touch-point correction of one move. */
typedef struct cmmcomp_correction {
  double mpe_um;           /**< maximum positioning error MPE [um] */
  double rpe_um;           /**< residual positioning error RPE [um], + = tip ahead of scale */
  double mae_um;           /**< maximum approach error MAE [um] */
  double rae_um;           /**< residual approach error RAE [um], + = tip ahead of scale */
  double correction_um[3]; /**< +RAE*d [um]: ADD it to the scale-reported touch point */
  uint32_t flags;          /**< CMMCOMP_FLAG_* bits */
  uint32_t sequence;       /**< request sequence echoed */
  uint64_t model_id;       /**< first 16 hex digits of the model file's SHA-256 checksum */
} cmmcomp_correction;

/** The 95 % prediction interval of one correction (docs/uncertainty.md): the true error lies
 * within the predicted one +- u95_um with 95 % probability, given the model and this move. */
typedef struct cmmcomp_interval {
  double u95_um[4];  /**< half-widths for MPE, RPE, MAE, RAE [um], >= 0 and finite; 0 = unknown */
  uint32_t flags;    /**< the correction's CMMCOMP_FLAG_* bits, CMMCOMP_FLAG_NO_UNCERTAINTY too */
  uint32_t reserved; /**< 0 */
} cmmcomp_interval;

/** Opaque compensator. */
typedef struct cmmcomp_compensator cmmcomp_compensator;

/** Library version, e.g. "0.1.0" (static string). */
CMMCOMP_CAPI_EXPORT const char* cmmcomp_version(void);
/** CMMCOMP_ABI_VERSION of the library actually loaded. */
CMMCOMP_CAPI_EXPORT unsigned cmmcomp_abi_version(void);

/** Creates a compensator from a model file. Setup only (allocates, reads the file).
 * Returns 0 and sets *out, or CMMCOMP_E_ARGUMENT, CMMCOMP_E_IO, CMMCOMP_E_MODEL (also for a
 * model whose interval is calibrated at another coverage than the 95 % that every U95 of this
 * ABI states), CMMCOMP_E_NO_MEMORY, CMMCOMP_E_INTERNAL (*out untouched). The model's training
 * conditions (PA and AA) are published with it (docs/compensator.md, "Domain"). */
CMMCOMP_CAPI_EXPORT int cmmcomp_create_from_file(const char* path, cmmcomp_compensator** out);
/** As cmmcomp_create_from_file, from `size` bytes of model JSON (size <=
 * CMMCOMP_MAX_MODEL_BYTES; the text need not be 0-terminated). */
CMMCOMP_CAPI_EXPORT int cmmcomp_create_from_memory(const void* json,
                                                   size_t size,
                                                   cmmcomp_compensator** out);
/** Hot swap: loads a model file and publishes it for every axis. Setup thread only, may run
 * while another thread calls cmmcomp_before_approach. On any error the old model keeps
 * serving. Returns 0 or a code as cmmcomp_create_from_file. */
CMMCOMP_CAPI_EXPORT int cmmcomp_reload_from_file(cmmcomp_compensator* c, const char* path);
/** As cmmcomp_reload_from_file, from memory. */
CMMCOMP_CAPI_EXPORT int cmmcomp_reload_from_memory(cmmcomp_compensator* c,
                                                   const void* json,
                                                   size_t size);
/** Predicts the errors of `in` and fills `out`. RT-safe and wait-free: no allocation, no lock,
 * no syscall. Returns 0 (check CMMCOMP_FLAG_OUTSIDE_DOMAIN: an input, or the PA or AA, outside
 * what the model file records it was trained at), CMMCOMP_E_ARGUMENT (null
 * pointer), CMMCOMP_E_INVALID_INPUT, CMMCOMP_E_NO_MODEL, CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED;
 * `out` is untouched on error. */
CMMCOMP_CAPI_EXPORT int cmmcomp_before_approach(const cmmcomp_compensator* c,
                                                const cmmcomp_move_request* in,
                                                cmmcomp_correction* out);
/** As cmmcomp_before_approach, and also fills `interval` with the correction's 95 %
 * prediction interval. An addition, so CMMCOMP_ABI_VERSION stays 1: callers of
 * cmmcomp_before_approach and its struct are unaffected. `out` and `interval` are untouched on
 * error. RT-safe and wait-free. */
CMMCOMP_CAPI_EXPORT int cmmcomp_before_approach_with_interval(const cmmcomp_compensator* c,
                                                              const cmmcomp_move_request* in,
                                                              cmmcomp_correction* out,
                                                              cmmcomp_interval* interval);
/** Destroys `c` (null is ignored). No other call on `c` may be running. Setup only. */
CMMCOMP_CAPI_EXPORT void cmmcomp_destroy(cmmcomp_compensator* c);
/** Static description of a return code; never null. RT-safe. */
CMMCOMP_CAPI_EXPORT const char* cmmcomp_strerror(int code);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* CMMCOMP_COMPENSATOR_H */
