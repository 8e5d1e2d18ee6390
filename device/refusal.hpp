// Why the bundle refused a request of the emulator's control plane (fault injection, settings),
// as a plain value: the JSON API maps each kind to its HTTP status and error code (web.md §8).
#pragma once

#include <cstdint>
#include <string>
#include <variant>

namespace mcemu::device {

struct Refusal {
  enum class Kind : std::uint8_t {
    syntax,       // the request is malformed (400 "syntax")
    unavailable,  // the feature is not there in this drive or build (503 "unavailable")
    conflict,     // not now, in this state (409 "conflict")
    not_found,    // nothing with that name (404 "not-found")
    forbidden,    // only from the command line or the config file (403 "forbidden")
  };
  Kind kind = Kind::syntax;
  std::string message;
};

// A result or the refusal.
template <class T>
using Outcome = std::variant<T, Refusal>;

}  // namespace mcemu::device
