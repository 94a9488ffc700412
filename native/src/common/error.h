// Errors inside the core are C++ exceptions carrying a moldtex_status; the C API layer
// catches every exception and turns it into a status code plus a message.
#pragma once
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

}  // namespace moldtex
