// Errors inside the core are C++ exceptions carrying a moldtex_status; the C API layer
// catches every exception and turns it into a status code plus a message.
#pragma once
#include <new>
#include <stdexcept>
#include <string>

#include "moldtex.h"

namespace moldtex {

class Error : public std::runtime_error {
 public:
  Error(moldtex_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  moldtex_status status() const { return status_; }

 private:
  moldtex_status status_;
};

[[noreturn]] inline void fail(moldtex_status status, const std::string& message) {
  throw Error(status, message);
}

// How a job on a worker thread (a bake, a domain build, a live run) ended: MOLDTEX_OK
// with no message when it returned, else the status and message of what it threw.
struct JobOutcome {
  moldtex_status status = MOLDTEX_OK;
  std::string message;
  // The MOLDTEX_BAKE_* state a job in this outcome ended in.
  uint32_t state() const {
    return status == MOLDTEX_OK                ? MOLDTEX_BAKE_FINISHED
           : status == MOLDTEX_ERROR_CANCELLED ? MOLDTEX_BAKE_CANCELLED
                                               : MOLDTEX_BAKE_FAILED;
  }
};

// Runs `job`, turning whatever it throws into a JobOutcome, so no exception leaves a
// worker thread (and none out of a C API call): an Error keeps its status and message;
// running out of memory (bad_alloc, or a container asked for more than it can hold)
// reports `out_of_memory`; anything else is an internal error, its message after
// `internal`.
template <class Job>
JobOutcome run_job(Job&& job, const char* out_of_memory, const char* internal) {
  try {
    job();
    return {};
  } catch (const Error& e) {
    return {e.status(), e.what()};
  } catch (const std::bad_alloc&) {
    return {MOLDTEX_ERROR_OUT_OF_MEMORY, out_of_memory};
  } catch (const std::length_error&) {
    return {MOLDTEX_ERROR_OUT_OF_MEMORY, out_of_memory};
  } catch (const std::exception& e) {
    return {MOLDTEX_ERROR_INTERNAL, std::string(internal) + e.what()};
  } catch (...) {
    return {MOLDTEX_ERROR_INTERNAL, std::string(internal) + "an exception of unknown kind"};
  }
}

}  // namespace moldtex
