#pragma once

#include <exception>
#include <string>

namespace plumetrace::cli {

/// Exit codes shared by every command.
inline constexpr int kBadInput = 2;
inline constexpr int kIoFailure = 3;
inline constexpr int kInterrupted = 130;
/// Out of memory: a failure of the machine, not of the input (input that asks for more memory
/// than any machine has is refused before anything is allocated, with kBadInput).
inline constexpr int kOutOfMemory = kIoFailure;
/// An exception nothing expected: a bug (never kBadInput or kIoFailure, never an abort).
inline constexpr int kInternalError = 1;

/// The exit code for an error: kBadInput for bad input (ConfigError, StoreError), kIoFailure
/// for I/O (IoError, StoreIoError, filesystem errors), kOutOfMemory for std::bad_alloc,
/// kInternalError for anything else.
int exit_code(const std::exception_ptr& error);

/// The advice for out of memory when the command gives none.
inline constexpr const char* kMemoryAdvice =
    "lower --threads, plume.capacity or the grid, or raise the memory limit";

/// Prints "plumetrace: error: " + `prefix` + the error's message on stderr; returns exit_code.
/// Out of memory is said with `memory_advice`, what the command lets one change.
int report_error(const std::exception_ptr& error, const std::string& prefix = "",
                 const std::string& memory_advice = kMemoryAdvice);

}  // namespace plumetrace::cli
