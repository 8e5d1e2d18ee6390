// An invalid value in the command line or the --config document of a drive: a one-line message
// naming the key or flag. The server prints it and exits with status 2 (server::UsageError is this
// type); the bundle throws it only while it is built, never afterwards.
#pragma once

#include <stdexcept>

namespace mcemu::device {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace mcemu::device
