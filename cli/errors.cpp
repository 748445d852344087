#include "errors.hpp"

#include <cstdio>
#include <filesystem>
#include <new>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/experiment/store.hpp"

namespace plumetrace::cli {

int exit_code(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const ConfigError&) {
    return kBadInput;
  } catch (const StoreIoError&) {
    return kIoFailure;
  } catch (const StoreError&) {
    return kBadInput;
  } catch (const std::filesystem::filesystem_error&) {
    return kIoFailure;
  } catch (const IoError&) {
    return kIoFailure;
  } catch (const std::bad_alloc&) {
    return kOutOfMemory;
  } catch (...) {
    return kInternalError;
  }
}

int report_error(const std::exception_ptr& error, const std::string& prefix,
                 const std::string& memory_advice) {
  const int code = exit_code(error);
  try {
    std::rethrow_exception(error);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "plumetrace: error: %sout of memory; results already stored are kept (%s)\n",
                 prefix.c_str(), memory_advice.c_str());
  } catch (const std::exception& e) {
    if (code == kInternalError) {
      std::fprintf(stderr, "plumetrace: internal error: %s%s (please report it)\n", prefix.c_str(),
                   e.what());
    } else {
      std::fprintf(stderr, "plumetrace: error: %s%s\n", prefix.c_str(), e.what());
    }
  } catch (...) {
    std::fprintf(stderr, "plumetrace: internal error: %san unknown exception (please report it)\n",
                 prefix.c_str());
  }
  return code;
}

}  // namespace plumetrace::cli
