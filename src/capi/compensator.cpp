// SPDX-License-Identifier: MIT
/// @file The C ABI (include/cmmcomp/compensator.h) over compensation::MoveCompensator.
#include <cmmcomp/compensator.h>

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/version.hpp>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <system_error>

#include "capi_types.hpp"

namespace cm = cmmcomp::compensation;

struct cmmcomp_compensator {
  cm::MoveCompensator compensator;
};

namespace {

// A file that cannot be opened is CMMCOMP_E_IO; everything the parser rejects is
// CMMCOMP_E_MODEL. The two are told apart here, before parsing.
int read_file(const char* path, std::string& text) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return CMMCOMP_E_IO;
  std::ifstream in(path, std::ios::binary);
  if (!in) return CMMCOMP_E_IO;
  char chunk[65536];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > CMMCOMP_MAX_MODEL_BYTES) return CMMCOMP_E_ARGUMENT;
  }
  if (in.bad()) return CMMCOMP_E_IO;
  return CMMCOMP_OK;
}

// Parses, then publishes to every axis. Publication validates each model again; the model
// file parser already guarantees it, so a failure there is internal.
// Either architecture (PV, PD, AV, AD [, Y]); see io/compensation_model_file.hpp.
int publish_text(cm::MoveCompensator& comp, const std::string& text, const std::string& source) {
  const auto file = cmmcomp::io::parse_compensation_model(text, source);
  for (int axis = 0; axis < cm::kMaxAxes; ++axis) {
    const cmmcomp::Status s = cmmcomp::io::publish(comp, axis, file);
    // kInvalidInput: the file is valid but not servable (an interval at another coverage).
    if (s == cmmcomp::Status::kInvalidInput) return CMMCOMP_E_MODEL;
    if (s != cmmcomp::Status::kOk) return CMMCOMP_E_INTERNAL;
  }
  return CMMCOMP_OK;
}

// Every entry point funnels its exceptions through here: nothing crosses the C boundary.
int code_of_current_exception() noexcept {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return CMMCOMP_E_NO_MEMORY;
  } catch (const cmmcomp::ConfigError&) {
    return CMMCOMP_E_MODEL;
  } catch (...) {
    return CMMCOMP_E_INTERNAL;
  }
}

// Reads `path` when given (else uses `text`), parses and publishes into `comp`. Throws; the
// callers turn exceptions into codes.
int load_and_publish(cm::MoveCompensator& comp, const std::string* text, const char* path) {
  std::string from_file;
  if (path != nullptr) {
    const int rc = read_file(path, from_file);
    if (rc != CMMCOMP_OK) return rc;
    text = &from_file;
  }
  return publish_text(comp, *text, path != nullptr ? path : "<memory>");
}

int create(const std::string* text, const char* path, cmmcomp_compensator** out) noexcept {
  try {
    auto c = std::make_unique<cmmcomp_compensator>();
    const int rc = load_and_publish(c->compensator, text, path);
    if (rc != CMMCOMP_OK) return rc;
    *out = c.release();
    return CMMCOMP_OK;
  } catch (...) {
    return code_of_current_exception();
  }
}

int reload(cmmcomp_compensator* c, const std::string* text, const char* path) noexcept {
  try {
    return load_and_publish(c->compensator, text, path);
  } catch (...) {
    return code_of_current_exception();
  }
}

}  // namespace

extern "C" {

const char* cmmcomp_version(void) { return CMMCOMP_VERSION_STRING; }

unsigned cmmcomp_abi_version(void) { return CMMCOMP_ABI_VERSION; }

int cmmcomp_create_from_file(const char* path, cmmcomp_compensator** out) {
  if (path == nullptr || out == nullptr) return CMMCOMP_E_ARGUMENT;
  return create(nullptr, path, out);
}

int cmmcomp_create_from_memory(const void* json, size_t size, cmmcomp_compensator** out) {
  if (json == nullptr || out == nullptr || size > CMMCOMP_MAX_MODEL_BYTES) {
    return CMMCOMP_E_ARGUMENT;
  }
  try {
    const std::string text(static_cast<const char*>(json), size);
    return create(&text, nullptr, out);
  } catch (...) {
    return code_of_current_exception();
  }
}

int cmmcomp_reload_from_file(cmmcomp_compensator* c, const char* path) {
  if (c == nullptr || path == nullptr) return CMMCOMP_E_ARGUMENT;
  return reload(c, nullptr, path);
}

int cmmcomp_reload_from_memory(cmmcomp_compensator* c, const void* json, size_t size) {
  if (c == nullptr || json == nullptr || size > CMMCOMP_MAX_MODEL_BYTES) {
    return CMMCOMP_E_ARGUMENT;
  }
  try {
    const std::string text(static_cast<const char*>(json), size);
    return reload(c, &text, nullptr);
  } catch (...) {
    return code_of_current_exception();
  }
}

int cmmcomp_before_approach(const cmmcomp_compensator* c,
                            const cmmcomp_move_request* in,
                            cmmcomp_correction* out) {
  if (c == nullptr || in == nullptr || out == nullptr) return CMMCOMP_E_ARGUMENT;
  if (in->axis >= CMMCOMP_MAX_AXES) return CMMCOMP_E_INVALID_INPUT;
  cm::Correction r;
  const cmmcomp::Status s = c->compensator.before_approach(cmmcomp::capi::to_move_request(*in), r);
  if (!cmmcomp::ok(s)) return static_cast<int>(s);
  cmmcomp::capi::write_correction(r, *out);
  return CMMCOMP_OK;
}

int cmmcomp_before_approach_with_interval(const cmmcomp_compensator* c,
                                          const cmmcomp_move_request* in,
                                          cmmcomp_correction* out,
                                          cmmcomp_interval* interval) {
  if (c == nullptr || in == nullptr || out == nullptr || interval == nullptr) {
    return CMMCOMP_E_ARGUMENT;
  }
  if (in->axis >= CMMCOMP_MAX_AXES) return CMMCOMP_E_INVALID_INPUT;
  cm::Correction r;
  const cmmcomp::Status s = c->compensator.before_approach(cmmcomp::capi::to_move_request(*in), r);
  if (!cmmcomp::ok(s)) return static_cast<int>(s);
  cmmcomp::capi::write_correction(r, *out);
  cmmcomp::capi::write_interval(r, *interval);
  return CMMCOMP_OK;
}

void cmmcomp_destroy(cmmcomp_compensator* c) { delete c; }

const char* cmmcomp_strerror(int code) {
  switch (code) {
    case CMMCOMP_OK:
      return "ok";
    case CMMCOMP_E_ARGUMENT:
      return "invalid argument (null pointer or size out of range)";
    case CMMCOMP_E_IO:
      return "cannot open or read the model file";
    case CMMCOMP_E_MODEL:
      return "not a valid cmmcomp model file (4 or 5 inputs, 3 sets, 4 outputs)";
    case CMMCOMP_E_NO_MEMORY:
      return "out of memory";
    case CMMCOMP_E_INTERNAL:
      return "internal error";
    case CMMCOMP_E_INVALID_INPUT:
      return "invalid move request (NaN, inf, non-positive, bad axis or direction)";
    case CMMCOMP_E_NO_MODEL:
      return "no model published";
    case CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED:
      return "outside the training domain (rejected by policy)";
    case CMMCOMP_E_BUSY:
      return "busy: a reader still uses the model buffer (nothing published)";
    default:
      return "unknown error code";
  }
}

}  // extern "C"
