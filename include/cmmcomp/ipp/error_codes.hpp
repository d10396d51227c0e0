// SPDX-License-Identifier: MIT
/// @file The I++ DME (ISO 22093) error numbers this project sends or reads: one table, the one
/// source of every number, severity and text (docs/protocol-ippdme.md, "Errors", is checked
/// against it by a test).
///
/// An error answer is `TAG ! Error(severity, number, "cause", "text")`: `number` four digits,
/// `cause` the command line that caused it (tag, space, command), `text` the table's text and,
/// after ": ", what exactly was wrong. Severities as the specification classes them: 0
/// information, 1 warning, 2 an error the command reports and the client may handle, 3 an error
/// that stops the command, 9 fatal. The numbers and severities are those of the I++ DME
/// specification 1.4 as NIST's I++ test suite (errorResponses.res) lists them.
/// Core-free, header-only, constexpr: usable by the parser's no-throw path.
#pragma once

#include <cstddef>

namespace cmmcomp::ipp {

/// The errors the server sends and the client names.
enum class ErrorCode : int {
  kBufferFull = 0,               ///< 0000: the server's command queue is full
  kIllegalTag = 1,               ///< 0001: no valid tag, a reserved tag, or a tag still in use
  kNoSpaceAtPos6 = 2,            ///< 0002: the 6th character is not a space
  kTransactionAborted = 6,       ///< 0006: AbortE ended this command
  kIllegalCharacter = 7,         ///< 0007: a control character, NUL or a byte above 0x7e
  kProtocolError = 8,            ///< 0008: a line that is not a command (or an over-long one)
  kUnsupportedCommand = 501,     ///< 0501: a command this server does not implement
  kIncorrectArguments = 502,     ///< 0502: wrong number, kind or syntax of arguments
  kArgumentOutOfRange = 504,     ///< 0504: a value outside its Min()..Max()
  kArgumentNotSupported = 506,   ///< 0506: a valid argument this server does not implement
  kIllegalCommand = 507,         ///< 0507: not an I++ DME command at all
  kBadContext = 508,             ///< 0508: not now (before StartSession, a second client, …)
  kBadArgument = 509,            ///< 0509: an argument of the right form with a wrong value
  kBadProperty = 510,            ///< 0510: a property this server does not have, or read-only
  kErrorProcessingMethod = 511,  ///< 0511: the machine could not run the command
  kDaemonDoesNotExist = 513,     ///< 0513: StopDaemon of a daemon that is not running
  kUseClearAllErrors = 514,      ///< 0514: the server is in its error state
  kTargetOutOfVolume = 1008,     ///< 1008: a target position outside the machine's volume
  kVectorHasNoNorm = 1010,       ///< 1010: an IJK of length zero
};

/// One row of the table.
struct ErrorInfo {
  ErrorCode code;
  int severity;      ///< 0, 1, 2, 3 or 9 (above)
  const char* text;  ///< the specification's text
};

inline constexpr ErrorInfo kErrors[] = {
    {ErrorCode::kBufferFull, 0, "Buffer full"},
    {ErrorCode::kIllegalTag, 2, "Illegal tag"},
    {ErrorCode::kNoSpaceAtPos6, 2, "No space at pos. 6"},
    {ErrorCode::kTransactionAborted, 2, "Transaction aborted (Use ClearAllErrors to Continue)"},
    {ErrorCode::kIllegalCharacter, 3, "Illegal character"},
    {ErrorCode::kProtocolError, 3, "Protocol error"},
    {ErrorCode::kUnsupportedCommand, 3, "Unsupported command"},
    {ErrorCode::kIncorrectArguments, 3, "Incorrect arguments"},
    {ErrorCode::kArgumentOutOfRange, 1, "Argument out of range"},
    {ErrorCode::kArgumentNotSupported, 3, "Argument not supported"},
    {ErrorCode::kIllegalCommand, 3, "Illegal command"},
    {ErrorCode::kBadContext, 3, "Bad context"},
    {ErrorCode::kBadArgument, 3, "Bad argument"},
    {ErrorCode::kBadProperty, 3, "Bad property"},
    {ErrorCode::kErrorProcessingMethod, 3, "Error processing method"},
    {ErrorCode::kDaemonDoesNotExist, 2, "Daemon does not exist"},
    {ErrorCode::kUseClearAllErrors, 2, "Use ClearAllErrors to continue"},
    {ErrorCode::kTargetOutOfVolume, 3, "Target position out of machine volume"},
    {ErrorCode::kVectorHasNoNorm, 2, "Vector has no norm"},
};
inline constexpr std::size_t kErrorCount = sizeof(kErrors) / sizeof(kErrors[0]);

/// The table's row of `code`.
constexpr const ErrorInfo& error_info(ErrorCode code) noexcept {
  for (const ErrorInfo& e : kErrors) {
    if (e.code == code) return e;
  }
  return kErrors[0];  // unreachable for an enumerator: every one has a row (tested)
}

/// The number as the wire writes it (0..9999).
constexpr int error_number(ErrorCode code) noexcept { return static_cast<int>(code); }

}  // namespace cmmcomp::ipp
